// process_epoch when the disk under the database is full at commit time: the epoch is kept
// (pending or back to pending at the next start), nothing is half-written, and it commits
// once there is room. In-process, on a real SQLite file on a small tmpfs.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "pipeline/epoch_pipeline.hpp"
#include "pipeline/sha256.hpp"
#include "tests/support/daemon_harness.hpp"
#include "tests/support/small_tmpfs.hpp"

namespace tlsmon::test {
namespace {

TEST(PipelineDiskFull, CommitRefusedKeepsTheEpochAndSucceedsLater) {
    Site site("pipefull");
    const fs::path db_folder = site.root / "db";
    const SmallTmpfs tmpfs(db_folder, "2m");
    if (!tmpfs.mounted()) {
        FAIL() << "cannot mount a tmpfs at " << db_folder << " (not root?): " << tmpfs.error();
    }

    Config config = parse_config("[paths]\ningest = \"ingest\"\ndatabase = \"db/tlsmon.sqlite\"\n",
                                 "test.toml", site.root);
    fs::create_directories(config.paths.archive);
    fs::create_directories(config.paths.quarantine);
    const fs::path scan = site.ingest() / "small_20260601T060000Z.ptx";
    fs::copy_file(fs::path(TLSMON_DATA_DIR) / "ptx/no-color.ptx", scan);

    EpochDatabase db = EpochDatabase::open(config.paths.database, EpochDatabase::Mode::read_write);
    SystemEventLog events;
    const PipelineConfig pipeline = pipeline_config(config);
    ReferenceCache cache{db};
    PipelineContext ctx{db, pipeline, events, cache};
    const EpochInsert ins =
        db.epochs().insert(NewEpoch{sha256_file(scan), 1780293600, scan, 100, std::nullopt});
    ASSERT_TRUE(ins.inserted);

    // SQLite reuses the space of a checkpointed WAL; truncate it (with the sqlite3 client)
    // so that the commit below needs new blocks.
    const auto truncate =
        shell("sqlite3 " + config.paths.database.string() + " 'PRAGMA wal_checkpoint(TRUNCATE)'");
    ASSERT_EQ(truncate.status, 0) << truncate.output;
    ASSERT_EQ(fs::file_size(config.paths.database.string() + "-wal"), 0u);
    fill_file_system(db_folder / "filler");
    const Epoch pending = *db.epochs().find(ins.id);
    EXPECT_EQ(process_epoch(ctx, pending), EpochOutcome::retry_later);
    EXPECT_TRUE(fs::exists(scan)) << "the file stays until its epoch is committed";
    EXPECT_GE(events.waiting(), 1u) << "the disk_full event waits for room";

    fs::remove(db_folder / "filler");
    db.epochs().recover_interrupted();  // what the daemon does before a retry
    const Epoch again = *db.epochs().find(ins.id);
    EXPECT_EQ(again.status, EpochStatus::pending);
    EXPECT_FALSE(again.point_count) << "nothing of the refused commit was stored";
    EXPECT_EQ(process_epoch(ctx, again), EpochOutcome::done);
    const Epoch done = *db.epochs().find(ins.id);
    EXPECT_EQ(done.status, EpochStatus::done);
    EXPECT_EQ(done.point_count, 15);
    EXPECT_FALSE(fs::exists(scan));
    EXPECT_TRUE(fs::exists(config.paths.archive / scan.filename()));
    events.flush(db);
    EXPECT_EQ(events.waiting(), 0u);
    bool recorded = false;
    for (const auto& e : db.series().events({}, std::string("disk_full"))) {
        recorded = recorded || e.epoch == ins.id;
    }
    EXPECT_TRUE(recorded);
}

}  // namespace
}  // namespace tlsmon::test
