// One retention pass (daemon/retention_pass.hpp) on real SQLite files: thinned in batches of
// `batch_epochs` (one event each), the file smaller afterwards whether it was made
// incremental (new) or not (an older database, converted once by a VACUUM), and a stop
// honoured between transactions.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include "daemon/retention_pass.hpp"
#include "tests/support/map_series.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;
constexpr UtcSeconds kStart = test::kSeriesStart;

RetentionPolicy policy() {
    RetentionPolicy p;
    p.keep_all_days = 3;
    p.keep_daily_days = 10;
    p.batch_epochs = 40;
    p.vacuum_pages = 100;
    return p;
}

TEST(RetentionPass, ThinsInBatchesAndShrinksTheFile) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    test::write_map_series(db, 20, 24, 2000, kStart);  // 480 epochs, 16 kB of maps each
    const auto r = run_retention_pass(db, policy());
    // Young: 3 days of 24 and the boundary's epoch; daily: days 10..16; weekly: days 0..9
    // start on Thu, Mon (day 4) -> 2.
    EXPECT_EQ(r.plan.kept_young, 3 * 24 + 1);
    EXPECT_EQ(r.plan.kept_daily, 7);
    EXPECT_EQ(r.plan.kept_weekly, 2);
    EXPECT_EQ(r.epochs_thinned, 480 - 73 - 7 - 2);
    EXPECT_EQ(r.map_bytes_deleted, r.epochs_thinned * 2 * 2000 * 4);
    EXPECT_FALSE(r.converted);
    EXPECT_FALSE(r.stopped);
    EXPECT_GT(r.pages_released, 0);
    EXPECT_LT(r.size_after, r.size_before - r.map_bytes_deleted * 9 / 10);
    EXPECT_EQ(test::sql_count(
                  path, "SELECT count(*) FROM system_events WHERE kind = 'retention_thinned'"),
              (r.epochs_thinned + 39) / 40);
    EXPECT_EQ(test::sql_count(path, "SELECT count(DISTINCT epoch_id) FROM core_point_arrays"),
              73 + 7 + 2);
    EXPECT_EQ(test::sql_count(path, "SELECT count(*) FROM zone_results"), 480);
    // A second pass finds nothing to do.
    const auto again = run_retention_pass(db, policy());
    EXPECT_EQ(again.epochs_thinned, 0);
    EXPECT_EQ(again.size_after, r.size_after);
}

TEST(RetentionPass, ConvertsAnOlderDatabaseOnceByAVacuum) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        test::write_map_series(db, 20, 24, 2000, kStart);
    }
    {
        // As a database made before incremental vacuum was chosen.
        SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE);
        raw.exec("PRAGMA auto_vacuum = NONE");
        raw.exec("VACUUM");
        ASSERT_EQ(raw.execAndGet("PRAGMA auto_vacuum").getInt(), 0);
    }
    auto db = EpochDatabase::open(path, Mode::read_write);
    EXPECT_FALSE(db.retention().incremental_vacuum());
    const auto r = run_retention_pass(db, policy());
    EXPECT_GT(r.epochs_thinned, 300);
    EXPECT_TRUE(r.converted);
    EXPECT_EQ(r.vacuum_error, "");
    EXPECT_TRUE(db.retention().incremental_vacuum());
    EXPECT_LT(r.size_after, r.size_before - r.map_bytes_deleted * 9 / 10);
    EXPECT_EQ(test::sql_count(
                  path, "SELECT count(*) FROM system_events WHERE kind = 'database_vacuumed'"),
              1);
    EXPECT_EQ(
        test::sql_count(path,
                        "SELECT count(*) FROM pragma_integrity_check WHERE integrity_check <> "
                        "'ok'"),
        0);
}

TEST(RetentionPass, StopsBetweenTransactions) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    test::write_map_series(db, 20, 24, 100, kStart);
    int asked = 0;
    const auto r = run_retention_pass(db, policy(), [&] { return ++asked > 2; });
    EXPECT_TRUE(r.stopped);
    EXPECT_EQ(r.epochs_thinned, 80);  // two batches of 40
    EXPECT_EQ(test::sql_count(
                  path, "SELECT count(*) FROM system_events WHERE kind = 'retention_thinned'"),
              2);
    // The next pass finishes the work.
    const auto rest = run_retention_pass(db, policy());
    EXPECT_EQ(rest.epochs_thinned, static_cast<std::int64_t>(r.plan.thin.size()) - 80);
    EXPECT_FALSE(rest.stopped);
}

}  // namespace
}  // namespace tlsmon
