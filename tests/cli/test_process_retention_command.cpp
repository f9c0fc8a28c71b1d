// `tlsmon retention` and `tlsmon epochs pin` through the built binary: pins with their audit,
// the plan, a pass; and `tlsmon retention run` killed (SIGKILL) again and again in the middle
// of its pass: every time the file is intact, every protected epoch and every zone value is
// there, and the run that is finally let finish leaves exactly what the plan said.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/map_series.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
using Mode = EpochDatabase::Mode;
constexpr UtcSeconds kStart = test::kSeriesStart;

TEST(RetentionCommand, KillNineDuringThinningLosesNothingThatShouldStay) {
    test::TempDir dir;
    const auto path = dir / "site.sqlite";
    test::MapSeries s;
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        // 60 days of hourly epochs; an alarm on day 2, a target excluded on day 25, a pin on
        // day 30: none of them the first of its day.
        s = test::write_map_series(db, 60, 24, 4000, kStart, {50}, {25 * 24 + 5});
        db.retention().pin(s.ids[30 * 24 + 7], "cli:test", "", kStart + 60 * 86400);
    }
    // One epoch per transaction and small vacuum steps: a pass of seconds to kill into.
    const auto config = dir / "site.toml";
    std::ofstream(config) << "[paths]\ndatabase = \"" << path.string()
                          << "\"\n[retention]\nkeep_all_days = 20\nkeep_daily_days = 40\n"
                             "batch_epochs = 1\nvacuum_pages = 16\n";
    const auto plan =
        test::run_tlsmon("retention plan --config " + config.string() + " --format json", false);
    ASSERT_EQ(plan.status, 0) << plan.out;
    const auto p = nlohmann::json::parse(plan.out);
    const auto to_thin = p.at("to_thin").get<std::int64_t>();
    const auto kept =
        p.at("kept_young").get<std::int64_t>() + p.at("kept_daily").get<std::int64_t>() +
        p.at("kept_weekly").get<std::int64_t>() + p.at("kept_protected").get<std::int64_t>();
    EXPECT_EQ(p.at("kept_protected").get<std::int64_t>(), 3);  // alarm, exclusion, pin
    EXPECT_EQ(kept + to_thin, 60 * 24);

    const int protected_index[] = {0, 50, 25 * 24 + 5, 30 * 24 + 7};
    int interrupted = 0;
    for (int ms : {150, 300, 450, 700, 1000, 1500}) {
        if (!test::killed_after({"retention", "run", "--config", config.string()}, ms)) continue;
        const auto with_maps =
            test::sql_count(path, "SELECT count(DISTINCT epoch_id) FROM core_point_arrays");
        if (with_maps > kept && with_maps < kept + to_thin) ++interrupted;
        ASSERT_EQ(
            test::sql_count(path,
                            "SELECT count(*) FROM pragma_integrity_check WHERE integrity_check"
                            " <> 'ok'"),
            0)
            << "killed after " << ms << " ms";
        EXPECT_EQ(test::sql_count(path, "SELECT count(*) FROM zone_results"), 60 * 24);
        EXPECT_EQ(test::sql_count(path,
                                  "SELECT count(*) FROM (SELECT epoch_id FROM core_point_arrays"
                                  " GROUP BY epoch_id HAVING count(*) <> 2)"),
                  0);
        // Every epoch with maps gone is recorded as thinned, in the same transaction.
        EXPECT_EQ(test::sql_count(path, "SELECT count(*) FROM thinned_maps"), 60 * 24 - with_maps);
        for (int i : protected_index) {
            EXPECT_EQ(
                test::sql_count(path, "SELECT count(*) FROM core_point_arrays WHERE epoch_id = " +
                                          std::to_string(s.ids[i])),
                2)
                << "epoch index " << i << ", killed after " << ms << " ms";
        }
    }
    EXPECT_GE(interrupted, 1) << "no kill landed inside a pass";

    const auto run =
        test::run_tlsmon("retention run --config " + config.string() + " --format json", false);
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_EQ(test::sql_count(path, "SELECT count(DISTINCT epoch_id) FROM core_point_arrays"),
              kept);
    EXPECT_EQ(test::sql_count(path, "SELECT count(*) FROM thinned_maps"), to_thin);
    EXPECT_EQ(test::sql_count(path, "PRAGMA freelist_count"), 0);
}

TEST(RetentionCommand, PinsAreAuditedAndAThinnedMapSaysSo) {
    test::TempDir dir;
    const auto path = dir / "site.sqlite";
    test::MapSeries s;
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        s = test::write_map_series(db, 40, 4, 100, kStart);
    }
    const std::string db = " --db " + path.string();
    const auto pinned_id = std::to_string(s.ids[9]);  // day 2, 06:00: thinned unless pinned
    auto r = test::run_tlsmon("epochs pin " + pinned_id + db + " --by ana --note 'crack survey'");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("epoch " + pinned_id + " pinned by ana"), std::string::npos) << r.out;
    r = test::run_tlsmon("epochs pin " + pinned_id + db);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("is pinned already"), std::string::npos) << r.out;
    r = test::run_tlsmon("epochs pin 9999" + db);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("no epoch 9999"), std::string::npos) << r.out;
    r = test::run_tlsmon("epochs pinned --format json" + db, false);
    ASSERT_EQ(r.status, 0) << r.out;
    const auto pins = nlohmann::json::parse(r.out);
    ASSERT_EQ(pins.size(), 1u);
    EXPECT_EQ(pins[0].at("epoch").get<std::int64_t>(), s.ids[9]);
    EXPECT_EQ(pins[0].at("pinned_by").get<std::string>(), "ana");
    EXPECT_EQ(pins[0].at("note").get<std::string>(), "crack survey");
    EXPECT_TRUE(pins[0].at("has_maps").get<bool>());

    // The defaults (30 days, then daily) with --db: days 0..8 are older than 30 days.
    r = test::run_tlsmon("retention run --format json" + db, false);
    ASSERT_EQ(r.status, 0) << r.out;
    const auto pass = nlohmann::json::parse(r.out);
    // Days 0..8: all but the first of each day; day 9 before 18:00: 06:00 and 12:00; not the
    // pinned one.
    EXPECT_EQ(pass.at("epochs_thinned").get<std::int64_t>(), 9 * 3 + 2 - 1);
    EXPECT_LT(pass.at("size_after").get<std::int64_t>(),
              pass.at("size_before").get<std::int64_t>());
    EXPECT_EQ(test::sql_count(
                  path, "SELECT count(*) FROM core_point_arrays WHERE epoch_id = " + pinned_id),
              2);
    r = test::run_tlsmon("query corepoints --epoch " + std::to_string(s.ids[10]) + db);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("thinned by the retention policy on"), std::string::npos) << r.out;

    r = test::run_tlsmon("epochs unpin " + pinned_id + db + " --by ana");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(test::sql_count(path,
                              "SELECT count(*) FROM system_events WHERE kind IN ('epoch_pinned',"
                              " 'epoch_unpinned') AND message LIKE '%by ana%'"),
              2);
    r = test::run_tlsmon("epochs unpin " + pinned_id + db);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("is not pinned"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace tlsmon
