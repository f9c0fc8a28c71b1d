// The retention's storage (storage/retention_store.hpp) on a real SQLite file: what is
// protected, pins with their events, a pin made after the plan honoured by the thinning, only
// maps deleted (the zone series whole), and the freed pages given back to the file system.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include <set>

#include "storage/epoch_database.hpp"
#include "tests/support/map_series.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;
constexpr UtcSeconds kStart = test::kSeriesStart;

RetentionPolicy short_policy() {
    RetentionPolicy p;
    p.keep_all_days = 5;
    p.keep_daily_days = 20;
    return p;
}

TEST(RetentionStore, ProtectsReferenceAlarmExclusionAndPinnedEpochs) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    // 40 days of 8 epochs; index 1 (day 0, 03:00) raises an alarm, index 90 (day 11, 06:00)
    // excludes a target; epoch index 250 (day 31, 06:00) is pinned below.
    const auto s = test::write_map_series(db, 40, 8, 200, kStart, {1}, {90});
    EXPECT_TRUE(db.retention().pin(s.ids[250], "cli:test", "crack seen", kStart + 40 * 86400));
    EXPECT_FALSE(db.retention().pin(s.ids[250], "cli:test", "", kStart + 40 * 86400));
    EXPECT_THROW(db.retention().pin(99999, "cli:test", "", kStart), StorageError);

    const auto plan = db.retention().plan(short_policy());
    EXPECT_EQ(plan.now, s.acquired.back());
    const std::set<EpochId> thin(plan.thin.begin(), plan.thin.end());
    // The reference (index 0) is also its day's and week's first: not counted as protected.
    for (int i : {0, 1, 90, 250}) EXPECT_FALSE(thin.count(s.ids[i])) << i;
    EXPECT_EQ(plan.kept_protected, 3);
    EXPECT_TRUE(thin.count(s.ids[2]));    // day 0, 06:00, nothing special
    EXPECT_TRUE(thin.count(s.ids[251]));  // beside the pinned one

    const auto pins = db.retention().pins();
    ASSERT_EQ(pins.size(), 1u);
    EXPECT_EQ(pins[0].epoch, s.ids[250]);
    EXPECT_EQ(pins[0].pinned_by, "cli:test");
    EXPECT_EQ(pins[0].note, "crack seen");
    EXPECT_TRUE(pins[0].has_maps);
    EXPECT_EQ(test::sql_count(path,
                              "SELECT count(*) FROM system_events WHERE kind = 'epoch_pinned' AND "
                              "message LIKE '%by cli:test: crack seen%'"),
              1);
}

TEST(RetentionStore, ThinsOnlyMapsAndHonoursAPinMadeAfterThePlan) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    const auto s = test::write_map_series(db, 30, 8, 500, kStart);
    const auto zone_rows = test::sql_count(path, "SELECT count(*) FROM zone_results");
    const auto plan = db.retention().plan(short_policy());
    ASSERT_GT(plan.thin.size(), 100u);
    const EpochId pinned_late = plan.thin[3];
    ASSERT_TRUE(db.retention().pin(pinned_late, "operator", "", kStart + 30 * 86400));

    const auto done = db.retention().thin(plan.thin, kStart + 30 * 86400);
    EXPECT_EQ(done.epochs, static_cast<std::int64_t>(plan.thin.size()) - 1);
    EXPECT_EQ(done.bytes, done.epochs * 2 * 500 * 4);  // two float32 maps of 500 values each
    EXPECT_TRUE(db.retention().has_maps(pinned_late));
    EXPECT_FALSE(db.retention().has_maps(plan.thin[0]));
    EXPECT_EQ(db.retention().maps_thinned_at(plan.thin[0]), kStart + 30 * 86400);
    EXPECT_EQ(db.retention().maps_thinned_at(pinned_late), std::nullopt);
    EXPECT_EQ(test::sql_count(path, "SELECT count(DISTINCT epoch_id) FROM core_point_arrays"),
              static_cast<std::int64_t>(s.ids.size() - plan.thin.size() + 1));
    EXPECT_EQ(test::sql_count(path, "SELECT count(*) FROM zone_results"), zone_rows);
    EXPECT_EQ(test::sql_count(
                  path, "SELECT count(*) FROM system_events WHERE kind = 'retention_thinned'"),
              1);
    // A second thinning of the same epochs finds nothing left and records nothing.
    EXPECT_EQ(db.retention().thin(plan.thin, kStart + 30 * 86400).epochs, 0);
    EXPECT_EQ(test::sql_count(
                  path, "SELECT count(*) FROM system_events WHERE kind = 'retention_thinned'"),
              1);

    // A new database is incremental: the freed pages go back to the file system.
    EXPECT_TRUE(db.retention().incremental_vacuum());
    const auto before = db.retention().size_bytes();
    const auto free_pages = db.retention().free_pages();
    EXPECT_GT(free_pages, 100);
    std::int64_t released = 0;
    while (const auto r = db.retention().release_free_pages(64)) {
        EXPECT_LE(r, 64);
        released += r;
    }
    EXPECT_EQ(released, free_pages);
    EXPECT_EQ(db.retention().free_pages(), 0);
    EXPECT_LT(db.retention().size_bytes(), before - done.bytes / 2);
    EXPECT_EQ(
        test::sql_count(path,
                        "SELECT count(*) FROM pragma_integrity_check WHERE integrity_check <> "
                        "'ok'"),
        0);
}

TEST(RetentionStore, UnpinRecordsWhoAndReturnsFalseWhenNotPinned) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    const auto s = test::write_map_series(db, 1, 4, 10, kStart);
    EXPECT_FALSE(db.retention().unpin(s.ids[1], "cli:test", kStart));
    ASSERT_TRUE(db.retention().pin(s.ids[1], "cli:test", "", kStart));
    EXPECT_TRUE(db.retention().unpin(s.ids[1], "cli:ana", kStart));
    EXPECT_TRUE(db.retention().pins().empty());
    EXPECT_EQ(
        test::sql_count(path,
                        "SELECT count(*) FROM system_events WHERE kind = 'epoch_unpinned' AND "
                        "message LIKE '%unpinned by cli:ana%'"),
        1);
}

}  // namespace
}  // namespace tlsmon
