// Epoch rows: insert-or-get by sha256, processing order, status transitions, crash recovery.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

NewEpoch scan(int n, UtcSeconds acquired) {
    return {test::fake_sha256(n), acquired, "/ingest/scan" + std::to_string(n) + ".ptx", 1000 + n,
            std::nullopt};
}

TEST(EpochLifecycle, InsertOrGetBySha256) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto first = db.epochs().insert(scan(1, 5000));
    EXPECT_TRUE(first.inserted);
    // The same bytes under another name (renamed or copied again) are the same epoch.
    NewEpoch again = scan(1, 9999);
    again.file_path = "/ingest/copy-of-scan1.ptx";
    const auto second = db.epochs().insert(again);
    EXPECT_FALSE(second.inserted);
    EXPECT_EQ(second.id, first.id);
    const auto e = db.epochs().find(first.id);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->file_path, "/ingest/scan1.ptx");  // the first sighting stands
    EXPECT_EQ(e->acquired, 5000);
    EXPECT_EQ(e->file_size, 1001);
    EXPECT_EQ(e->status, EpochStatus::pending);
    EXPECT_EQ(db.epochs().pending().size(), 1u);
    EXPECT_EQ(db.epochs().find_by_sha256(test::fake_sha256(1))->id, first.id);
    EXPECT_FALSE(db.epochs().find_by_sha256(test::fake_sha256(2)));
}

TEST(EpochLifecycle, MalformedSha256IsRefused) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    NewEpoch bad = scan(1, 0);
    bad.sha256 = std::string(64, 'A');  // upper case: not the canonical form
    EXPECT_THROW(db.epochs().insert(bad), StorageError);
    bad.sha256 = "abc";
    EXPECT_THROW(db.epochs().insert(bad), StorageError);
    EXPECT_TRUE(db.epochs().pending().empty());
}

TEST(EpochLifecycle, PendingInAcquisitionOrder) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    // Discovered out of order (backlog after downtime); two with the same time.
    const auto c = db.epochs().insert(scan(3, 3000)).id;
    const auto a = db.epochs().insert(scan(1, 1000)).id;
    const auto b1 = db.epochs().insert(scan(2, 2000)).id;
    const auto b2 = db.epochs().insert(scan(4, 2000)).id;
    const auto pending = db.epochs().pending();
    ASSERT_EQ(pending.size(), 4u);
    EXPECT_EQ(pending[0].id, a);
    EXPECT_EQ(pending[1].id, b1);
    EXPECT_EQ(pending[2].id, b2);
    EXPECT_EQ(pending[3].id, c);
    ASSERT_TRUE(db.epochs().claim(a));
    const auto rest = db.epochs().pending();
    ASSERT_EQ(rest.size(), 3u);
    EXPECT_EQ(rest[0].id, b1);
}

TEST(EpochLifecycle, StatusTransitions) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto id = db.epochs().insert(scan(1, 1000)).id;
    EXPECT_TRUE(db.epochs().claim(id));
    EXPECT_FALSE(db.epochs().claim(id));  // already processing
    EXPECT_EQ(db.epochs().find(id)->status, EpochStatus::processing);
    db.epochs().release(id);  // e.g. disk full: back to the queue
    EXPECT_EQ(db.epochs().find(id)->status, EpochStatus::pending);
    EXPECT_THROW(db.epochs().release(id), StorageError);  // not processing

    EXPECT_TRUE(db.epochs().claim(id));
    EXPECT_THROW(db.epochs().fail(id, ""), StorageError);  // a reason is required
    db.epochs().fail(id, "line 7: expected 4 numbers", "/var/lib/tlsmon/quarantine/scan1.ptx");
    auto e = db.epochs().find(id);
    EXPECT_EQ(e->status, EpochStatus::failed);
    EXPECT_EQ(e->reason, "line 7: expected 4 numbers");
    EXPECT_EQ(e->archive_path.value_or(""), "/var/lib/tlsmon/quarantine/scan1.ptx");
    EXPECT_FALSE(db.epochs().claim(id));                             // final
    EXPECT_THROW(db.epochs().reject(id, "too late"), StorageError);  // final
    EXPECT_THROW(db.results().commit(id, EpochResults{}), StorageError);

    const auto r = db.epochs().insert(scan(2, 2000)).id;
    ASSERT_TRUE(db.epochs().claim(r));
    db.epochs().reject(r, "registration RMS 12 mm > 5 mm");
    EXPECT_EQ(db.epochs().find(r)->status, EpochStatus::rejected);
    EXPECT_EQ(db.epochs().find(r)->reason, "registration RMS 12 mm > 5 mm");
    EXPECT_FALSE(db.epochs().find(r)->archive_path);
    EXPECT_THROW(db.epochs().release(999), StorageError);  // no such epoch
}

// An epoch whose file was renamed or vanished takes its content's new file if it was never
// read; an epoch that was read, or whose file was moved to quarantine, does not.
TEST(EpochLifecycle, RelocateOnlyUnreadEpochs) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const EpochId pending = db.epochs().insert(scan(1, 1000)).id;
    EXPECT_TRUE(db.epochs().relocate(pending, "/ingest/renamed1.ptx"));
    EXPECT_EQ(db.epochs().find(pending)->file_path, "/ingest/renamed1.ptx");
    EXPECT_EQ(db.epochs().find(pending)->status, EpochStatus::pending);

    const EpochId vanished = db.epochs().insert(scan(2, 2000)).id;
    ASSERT_TRUE(db.epochs().claim(vanished));
    db.epochs().fail(vanished, "the file vanished before it was processed");
    EXPECT_TRUE(db.epochs().relocate(vanished, "/ingest/renamed2.ptx"));
    EXPECT_EQ(db.epochs().find(vanished)->status, EpochStatus::pending);
    EXPECT_EQ(db.epochs().find(vanished)->reason, "");
    EXPECT_EQ(db.epochs().find(vanished)->file_path, "/ingest/renamed2.ptx");

    const EpochId quarantined = db.epochs().insert(scan(3, 3000)).id;
    ASSERT_TRUE(db.epochs().claim(quarantined));
    db.epochs().fail(quarantined, "corrupt", "/quarantine/scan3.ptx");
    EXPECT_FALSE(db.epochs().relocate(quarantined, "/ingest/again3.ptx"));
    EXPECT_EQ(db.epochs().find(quarantined)->status, EpochStatus::failed);

    const EpochId processing = db.epochs().insert(scan(4, 4000)).id;
    ASSERT_TRUE(db.epochs().claim(processing));
    EXPECT_FALSE(db.epochs().relocate(processing, "/ingest/again4.ptx"));
    db.results().commit(processing, EpochResults{});
    EXPECT_FALSE(db.epochs().relocate(processing, "/ingest/again4.ptx"));
    EXPECT_EQ(db.epochs().find(processing)->file_path, "/ingest/scan4.ptx");
}

// A writer killed while an epoch is `processing` leaves it so; the next start puts it back.
TEST(EpochLifecycle, CrashLeavesProcessingWhichRecoveryRequeues) {
    test::TempDir dir;
    const auto path = dir / "e.sqlite";
    EpochId id = 0;
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        id = db.epochs().insert(scan(1, 1000)).id;
        db.epochs().insert(scan(2, 2000));
    }
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        auto db = EpochDatabase::open(path, Mode::read_write);
        db.epochs().claim(id);
        raise(SIGKILL);  // no destructor, no close: as a crash
        _exit(1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status));
    auto db = EpochDatabase::open(path, Mode::read_write);
    EXPECT_EQ(db.epochs().find(id)->status, EpochStatus::processing);
    EXPECT_EQ(db.epochs().pending().size(), 1u);
    EXPECT_EQ(db.epochs().recover_interrupted(), 1);
    EXPECT_EQ(db.epochs().recover_interrupted(), 0);
    const auto pending = db.epochs().pending();
    ASSERT_EQ(pending.size(), 2u);
    EXPECT_EQ(pending[0].id, id);
}

TEST(EpochLifecycle, ReferenceEpochIsSetOnce) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    EXPECT_FALSE(db.epochs().reference());
    const auto a = db.epochs().insert(scan(1, 1000)).id;
    const auto b = db.epochs().insert(scan(2, 2000)).id;
    db.epochs().set_reference(a);
    db.epochs().set_reference(a);  // same: no-op
    EXPECT_THROW(db.epochs().set_reference(b), StorageError);
    EXPECT_EQ(db.epochs().reference(), a);
    EXPECT_THROW(db.epochs().set_reference(12345), StorageError);  // not reached: already set
}

TEST(EpochLifecycle, ReferenceEpochMustExist) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    EXPECT_THROW(db.epochs().set_reference(12345), StorageError);  // foreign key
    EXPECT_FALSE(db.epochs().reference());
}

TEST(EpochLifecycle, StationsUpsertByName) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto s1 = db.site().upsert_station("north", {1.0, 2.0, 3.0});
    const auto s2 = db.site().upsert_station("north", {1.5, 2.0, 3.0});
    EXPECT_EQ(s1, s2);
    const auto all = db.site().stations();
    ASSERT_EQ(all.size(), 1u);
    EXPECT_DOUBLE_EQ(all[0].position[0], 1.5);
    NewEpoch e = scan(1, 1000);
    e.station = s1;
    EXPECT_EQ(db.epochs().find(db.epochs().insert(e).id)->station, s1);
    e = scan(2, 1000);
    e.station = 777;  // no such station
    EXPECT_THROW(db.epochs().insert(e), StorageError);
}

}  // namespace
}  // namespace tlsmon
