// `tlsmon backup`: the built binary copies a database another process is writing to; the
// copy opens with `tlsmon query`; an existing file is refused with the reason.
#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <thread>

#include "storage/epoch_database.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
using Mode = EpochDatabase::Mode;

std::string sha(int n) {
    std::string s = std::to_string(n);
    return std::string(64 - s.size(), 'b') + s;
}

TEST(BackupCommand, CopiesWhileAWriterCommitsAndTheCopyIsQueried) {
    test::TempDir dir;
    const auto path = dir / "site.sqlite";
    std::atomic<bool> stop{false};
    std::atomic<int> written{0};
    std::thread writer([&] {
        auto db = EpochDatabase::open(path, Mode::read_write);
        for (int i = 0; !stop; ++i) {
            db.epochs().insert({sha(i), 1772366400 + 900 * i, "/ingest/s.ptx", 1, std::nullopt});
            written = i + 1;
        }
    });
    while (written < 50) std::this_thread::yield();
    fs::create_directory(dir / "backups");
    const auto run = test::run_tlsmon(
        "backup " + (dir / "backups").string() + " --db " + path.string() + " --format json",
        false);
    const int after = written;
    stop = true;
    writer.join();
    ASSERT_EQ(run.status, 0) << run.out;
    const auto j = nlohmann::json::parse(run.out);
    const fs::path copy = j.at("backup").get<std::string>();
    EXPECT_EQ(copy.parent_path(), dir / "backups");
    EXPECT_EQ(j.at("source").get<std::string>(), path.string());
    EXPECT_EQ(j.at("schema_version").get<int>(), EpochDatabase::latest_schema_version());
    EXPECT_EQ(j.at("quick_check").get<std::string>(), "ok");
    const auto epochs = j.at("epochs").get<std::int64_t>();
    EXPECT_GE(epochs, 50);
    EXPECT_LE(epochs, after);
    EXPECT_EQ(j.at("bytes").get<std::int64_t>(), static_cast<std::int64_t>(fs::file_size(copy)));

    const auto listed =
        test::run_tlsmon("query epochs --db " + copy.string() + " --format json", false);
    ASSERT_EQ(listed.status, 0) << listed.out;
    EXPECT_EQ(static_cast<std::int64_t>(nlohmann::json::parse(listed.out).size()), epochs);

    // The same name again: refused, the copy untouched.
    const auto size = fs::file_size(copy);
    const auto again = test::run_tlsmon("backup " + copy.string() + " --db " + path.string());
    EXPECT_EQ(again.status, 1);
    EXPECT_NE(again.out.find("tlsmon backup: " + copy.string() + ": backing up"), std::string::npos)
        << again.out;
    EXPECT_NE(again.out.find("exists already; not overwritten"), std::string::npos) << again.out;
    EXPECT_EQ(fs::file_size(copy), size);
}

}  // namespace
}  // namespace tlsmon
