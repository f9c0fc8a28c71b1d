// move_file to another file system (a small tmpfs, so this needs root): copy, sync, rename,
// remove the source; with no room for the copy the source stays and nothing is left behind.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "pipeline/epoch_files.hpp"
#include "tests/support/small_tmpfs.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

TEST(MoveFile, MoveFileToAnotherFileSystemCopiesSyncsAndRemoves) {
    const test::TempDir d;
    const test::SmallTmpfs other(d / "other", "1m");
    if (!other.mounted()) FAIL() << "cannot mount a tmpfs (not root?): " << other.error();
    test::write_file(d / "scan.ptx", "bytes of a scan");
    move_file(d / "scan.ptx", d / "other/scan.ptx");
    EXPECT_FALSE(fs::exists(d / "scan.ptx"));
    EXPECT_EQ(test::read_file(d / "other/scan.ptx"), "bytes of a scan");
    EXPECT_FALSE(fs::exists(d / "other/.scan.ptx.part"));
    // No room for the copy: the source stays, nothing half-copied is left.
    test::write_file(d / "big.ptx", std::string(2 << 20, 'x'));
    EXPECT_THROW(move_file(d / "big.ptx", d / "other/big.ptx"), Error);
    EXPECT_EQ(fs::file_size(d / "big.ptx"), 2u << 20);
    EXPECT_FALSE(fs::exists(d / "other/big.ptx"));
    EXPECT_FALSE(fs::exists(d / "other/.big.ptx.part"));
}

}  // namespace
}  // namespace tlsmon
