// `tlsmon archive plan|run` through the built binary, and `tlsmon archive run` killed
// (SIGKILL) again and again in the middle of its pass: after every kill each epoch's scan is
// either recorded as removed or there, whole (the ingested file with its sha256, or an E57
// with the sha256 recorded for it), the database intact; the run finally let finish leaves
// what the plan said, with no partial file behind.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/archive_series.hpp"
#include "tests/support/map_series.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
using Mode = EpochDatabase::Mode;

// Every epoch's scan is accounted for: removed (as recorded), or at its archive_path with
// the content the database says.
void expect_every_scan_accounted_for(const fs::path& database, const std::string& when) {
    SQLite::Database db(database.string(), SQLite::OPEN_READWRITE);
    SQLite::Statement s(db,
                        "SELECT e.archive_path, e.sha256, coalesce(a.action, ''),"
                        " coalesce(a.sha256_after, '') FROM epochs e LEFT JOIN archived_scans a"
                        " ON a.epoch_id = e.id");
    int epochs = 0;
    while (s.executeStep()) {
        ++epochs;
        const std::string path = s.getColumn(0).getString(), action = s.getColumn(2).getString();
        if (action == "removed") continue;
        ASSERT_TRUE(fs::exists(path)) << path << ", " << when;
        const std::string want =
            action == "reencoded" ? s.getColumn(3).getString() : s.getColumn(1).getString();
        EXPECT_EQ(sha256_file(path), want) << path << ", " << when;
    }
    EXPECT_GT(epochs, 0);
    EXPECT_EQ(db.execAndGet("SELECT count(*) FROM pragma_integrity_check WHERE integrity_check"
                            " <> 'ok'")
                  .getInt(),
              0)
        << when;
}

TEST(ArchiveCommand, KillNineDuringAPassLosesNoScanThatShouldStay) {
    test::TempDir dir;
    const auto database = dir / "site.sqlite";
    const auto archive = dir / "archive";
    fs::create_directories(archive);
    std::vector<EpochId> ids;
    {
        auto db = EpochDatabase::open(database, Mode::read_write);
        // 40 days of 8 scans; an alarm on day 3 and a pin on day 20, neither a day's first.
        ids = test::write_archive_series(db, archive, 40 * 8, 8, test::kSeriesStart, {3 * 8 + 2});
        db.retention().pin(ids[20 * 8 + 5], "cli:test", "", 0);
    }
    const auto config = dir / "site.toml";
    std::ofstream(config) << "[paths]\ndatabase = \"" << database.string() << "\"\narchive = \""
                          << archive.string() << "\"\ningest = \"" << (dir / "ingest").string()
                          << "\"\nquarantine = \"" << (dir / "quarantine").string()
                          << "\"\n[archive]\nenabled = true\nkeep_all_days = 5\n"
                             "keep_daily_days = 15\nreencode = \"e57\"\nbatch_scans = 1\n";
    const auto plan =
        test::run_tlsmon("archive plan --config " + config.string() + " --format json", false);
    ASSERT_EQ(plan.status, 0) << plan.out;
    const auto p = nlohmann::json::parse(plan.out);
    EXPECT_EQ(p.at("scans").get<std::int64_t>(), 40 * 8);
    EXPECT_EQ(p.at("kept_protected").get<std::int64_t>(), 2);  // the alarm's, the pinned
    const auto to_remove = p.at("to_remove").get<std::int64_t>();
    const auto to_reencode = p.at("to_reencode").get<std::int64_t>();
    EXPECT_EQ(p.at("kept_young").get<std::int64_t>() + p.at("kept_daily").get<std::int64_t>() +
                  p.at("kept_weekly").get<std::int64_t>() + 2 + to_remove,
              40 * 8);
    // Kept past the young tier, but for the reference.
    EXPECT_EQ(to_reencode, p.at("kept_daily").get<std::int64_t>() +
                               p.at("kept_weekly").get<std::int64_t>() + 2 - 1);

    int interrupted = 0;
    for (int ms : {100, 200, 350, 500, 800, 1200}) {
        if (!test::killed_after({"archive", "run", "--config", config.string()}, ms)) continue;
        ++interrupted;
        expect_every_scan_accounted_for(database, "killed after " + std::to_string(ms) + " ms");
    }
    EXPECT_GE(interrupted, 1) << "no kill landed inside a pass";

    const auto run = test::run_tlsmon("archive run --config " + config.string() + " --format json");
    ASSERT_EQ(run.status, 0) << run.out;
    expect_every_scan_accounted_for(database, "after the last run");
    EXPECT_EQ(
        test::sql_count(database, "SELECT count(*) FROM archived_scans WHERE action = 'removed'"),
        to_remove);
    EXPECT_EQ(
        test::sql_count(database, "SELECT count(*) FROM archived_scans WHERE action = 'reencoded'"),
        to_reencode);
    // In the folder: exactly the kept scans, and the pass's lock file.
    std::int64_t files = 0;
    for (const auto& f : fs::directory_iterator(archive)) {
        EXPECT_FALSE(f.path().string().ends_with(".part")) << f.path();
        files += f.path().filename() != ".archive-pass.lock";
    }
    EXPECT_EQ(files, 40 * 8 - to_remove);
    // The reference's scan, the alarm's and the pinned one are there.
    for (const auto i : {0, 3 * 8 + 2, 20 * 8 + 5}) {
        EXPECT_FALSE(fs::exists(archive / ("scan_" + std::to_string(i) + ".ptx")) &&
                     fs::exists(archive / ("scan_" + std::to_string(i) + ".e57")));
        EXPECT_TRUE(fs::exists(archive / ("scan_" + std::to_string(i) + ".ptx")) ||
                    fs::exists(archive / ("scan_" + std::to_string(i) + ".e57")))
            << i;
    }
    EXPECT_TRUE(fs::exists(archive / "scan_0.ptx"));  // the reference, byte for byte
}

TEST(ArchiveCommand, NeedsTheSiteConfigurationAndItsConsent) {
    test::TempDir dir;
    const auto database = dir / "site.sqlite";
    { EpochDatabase::open(database, Mode::read_write); }
    auto r = test::run_tlsmon("archive plan --db " + database.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("--config is needed"), std::string::npos) << r.out;
    const auto config = dir / "site.toml";
    std::ofstream(config) << "[paths]\ndatabase = \"" << database.string() << "\"\n";
    r = test::run_tlsmon("archive run --config " + config.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("archive.enabled = false"), std::string::npos) << r.out;
    r = test::run_tlsmon("archive plan --config " + config.string() + " --format json", false);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out).at("scans").get<std::int64_t>(), 0);
}

}  // namespace
}  // namespace tlsmon
