// Readers while the daemon writes (WAL), and SQLite's codes classified as disk full or busy
// (a real full disk: test_process_disk_full.cpp).
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <thread>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

EpochResults one_zone(double value) {
    EpochResults r;
    r.zone_results = {{"deck", "m3c2_mean_m", value, 0.002, 50, false}};
    return r;
}

TEST(Concurrency, ReaderDoesNotWaitForAnOpenWriteTransaction) {
    test::TempDir dir;
    const auto path = dir / "e.sqlite";
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        db.epochs().insert({test::fake_sha256(1), 1000, "/i/a.ptx", 1, std::nullopt});
    }
    // Another process's writer in the middle of a transaction, holding the write lock.
    SQLite::Database writer(path.string(), SQLite::OPEN_READWRITE);
    SQLite::Transaction tx(writer, SQLite::TransactionBehavior::IMMEDIATE);
    writer.exec(
        "INSERT INTO epochs (sha256, acquired, discovered, updated, file_path, file_size)"
        " VALUES ('" +
        test::fake_sha256(2) + "', 2000, 0, 0, '/i/b.ptx', 1)");

    const auto start = std::chrono::steady_clock::now();
    auto reader = EpochDatabase::open(path, Mode::read_only, std::chrono::milliseconds(5000));
    const auto s = reader.series().status_summary();
    const auto waited = std::chrono::steady_clock::now() - start;
    EXPECT_EQ(s.epochs_by_status.at(EpochStatus::pending), 1);  // not the uncommitted one
    EXPECT_LT(waited, std::chrono::seconds(1));
    // A second writer does wait, and after the busy timeout says so distinguishably.
    auto other = EpochDatabase::open(path, Mode::read_write, std::chrono::milliseconds(100));
    try {
        other.epochs().insert({test::fake_sha256(3), 3000, "/i/c.ptx", 1, std::nullopt});
        FAIL() << "wrote while another connection held the write lock";
    } catch (const StorageError& e) {
        EXPECT_TRUE(e.busy()) << e.what();
        EXPECT_FALSE(e.disk_full()) << e.what();
    }
    tx.commit();
    EXPECT_EQ(reader.epochs().pending().size(), 2u);
}

TEST(Concurrency, ReadersSeeWholeEpochsWhileTheWriterCommits) {
    test::TempDir dir;
    const auto path = dir / "e.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    db.site().upsert_zone("deck", "{}");
    constexpr int kEpochs = 150;
    std::atomic<bool> writing{true};
    std::thread writer([&] {
        for (int i = 0; i < kEpochs; ++i) {
            const auto id =
                db.epochs()
                    .insert({test::fake_sha256(i + 1), 1000 + i, "/i/s.ptx", 1, std::nullopt})
                    .id;
            db.epochs().claim(id);
            db.results().commit(id, one_zone(0.001 * i));
        }
        writing = false;
    });
    auto reader = EpochDatabase::open(path, Mode::read_only);
    int reads = 0;
    std::int64_t last_done = 0;
    bool consistent = true;
    while (writing || reads == 0) {
        const auto s = reader.series().status_summary();
        const auto done = s.epochs_by_status.at(EpochStatus::done);
        const auto series = reader.series().points("deck", "m3c2_mean_m", {});
        // Series read after the summary: at least as many rows, never a torn epoch.
        if (done < last_done || static_cast<std::int64_t>(series.size()) < done) {
            consistent = false;
        }
        last_done = done;
        ++reads;
    }
    writer.join();
    EXPECT_TRUE(consistent);
    EXPECT_GT(reads, 1);
    EXPECT_EQ(reader.series().status_summary().epochs_by_status.at(EpochStatus::done), kEpochs);
    EXPECT_EQ(reader.series().points("deck", "m3c2_mean_m", {}).size(),
              static_cast<std::size_t>(kEpochs));
}

TEST(DiskFull, ErrorCodesAreClassified) {
    EXPECT_TRUE(StorageError("x", SQLITE_FULL, SQLITE_FULL).disk_full());
    EXPECT_TRUE(StorageError("x", SQLITE_IOERR, SQLITE_IOERR_WRITE).disk_full());
    EXPECT_FALSE(StorageError("x", SQLITE_CONSTRAINT, SQLITE_CONSTRAINT_UNIQUE).disk_full());
    EXPECT_FALSE(StorageError("x").disk_full());
    EXPECT_TRUE(StorageError("x", SQLITE_BUSY, SQLITE_BUSY).busy());
    EXPECT_FALSE(StorageError("x", SQLITE_FULL, SQLITE_FULL).busy());
}

}  // namespace
}  // namespace tlsmon
