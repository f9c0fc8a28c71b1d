// read_scans (from the file) and parse_scans (from its bytes in memory) must give the same
// scans for every format, and the format of a file with no known extension is found from
// its first bytes.
#include <gtest/gtest.h>

#include "formats/format_error.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
const fs::path kData = TLSMON_DATA_DIR;

void expect_same_scans(const std::vector<Scan>& a, const std::vector<Scan>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        ASSERT_EQ(a[k].size(), b[k].size()) << "scan " << k;
        ASSERT_GT(a[k].size(), 0u);
        for (std::size_t i : {std::size_t{0}, a[k].size() / 2, a[k].size() - 1}) {
            EXPECT_EQ(a[k].xyz[i], b[k].xyz[i]) << "scan " << k << " point " << i;
        }
        EXPECT_EQ(a[k].intensity, b[k].intensity);
        EXPECT_EQ(a[k].grid.has_value(), b[k].grid.has_value());
        EXPECT_TRUE(a[k].pose.isApprox(b[k].pose, 0.0));
    }
}

TEST(ScanFile, BytesInMemoryGiveTheSameScansAsTheFile) {
    for (const char* name :
         {"ptx/multiple-and-transform.ptx", "ptx/pumpA_from_e57.ptx", "xyz/plane_horizontal_t1.xyz",
          "las/laspy/test1_4.las", "las/libLAS/1.2-with-color.las",
          "e57/pumpARowColumnIndexNoInvalidPoints.e57"}) {
        SCOPED_TRACE(name);
        const fs::path path = kData / name;
        expect_same_scans(read_scans(path), parse_scans(test::read_file(path), path));
    }
}

TEST(ScanFile, FormatWithoutKnownExtensionComesFromTheFirstBytes) {
    test::TempDir dir;
    const fs::path las = kData / "las/laspy/simple.las";
    const fs::path renamed = test::write_file(dir / "scan.bin", test::read_file(las));
    EXPECT_EQ(detect_format(renamed), ScanFormat::las);
    const auto scans = parse_scans(test::read_file(renamed), renamed);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].size(), 1065u);

    const fs::path text = test::write_file(dir / "notes.bin", "hello\n");
    EXPECT_EQ(detect_format(text), ScanFormat::unknown);
    EXPECT_THROW(parse_scans(test::read_file(text), text), FormatError);
}

}  // namespace
}  // namespace tlsmon
