// The online backup: one consistent snapshot while another connection writes, the source's
// permissions, never an overwrite or a partial file; and the copy before a schema migration.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <thread>

#include "fake_sha256.hpp"
#include "schema_1_database.hpp"
#include "storage/database_backup.hpp"
#include "storage/epoch_database.hpp"
#include "storage/schema_migrations.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
using Mode = EpochDatabase::Mode;

std::int64_t count(SQLite::Database& db, const char* sql) {
    return db.execAndGet(sql).getInt64();
}

mode_t permission_bits(const fs::path& p) {
    struct stat st {};
    EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
    return st.st_mode & 0777;
}

// 40 MB of pages, so the copy takes several steps, while a second connection inserts
// epochs as fast as it can. The copy must be one snapshot: its epoch count between the
// counts before and after, and the status counters (kept by triggers in each insert's
// transaction) equal to it.
TEST(DatabaseBackup, OneSnapshotWhileAnotherConnectionWrites) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        db.epochs().insert({test::fake_sha256(0), 1000, "/ingest/0.ptx", 1, std::nullopt});
    }
    {
        SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE);
        raw.exec("CREATE TABLE filler (b BLOB)");
        SQLite::Statement fill(raw, "INSERT INTO filler VALUES (zeroblob(1000000))");
        for (int i = 0; i < 40; ++i) fill.exec(), fill.reset();
    }
    ::chmod(path.c_str(), 0640);

    std::atomic<bool> stop{false};
    std::atomic<int> written{1};
    std::thread writer([&] {
        auto db = EpochDatabase::open(path, Mode::read_write);
        for (int i = 1; !stop; ++i) {
            db.epochs().insert(
                {test::fake_sha256(i), 1000 + 900 * i, "/ingest/x.ptx", 1, std::nullopt});
            written = i + 1;
        }
    });
    while (written < 20) std::this_thread::yield();
    const int before = written;
    const auto copy = dir / "copy.sqlite";
    const DatabaseBackup b = backup_database(path, copy);
    const int after = written;
    stop = true;
    writer.join();

    EXPECT_EQ(b.path, copy);
    EXPECT_EQ(b.schema_version, EpochDatabase::latest_schema_version());
    EXPECT_GE(b.epochs, before);
    EXPECT_LE(b.epochs, after);
    EXPECT_EQ(b.bytes, static_cast<std::int64_t>(fs::file_size(copy)));
    EXPECT_GT(b.bytes, 40'000'000);
    EXPECT_FALSE(fs::exists(copy.string() + ".part"));
    EXPECT_FALSE(fs::exists(copy.string() + "-wal"));
    EXPECT_EQ(permission_bits(copy), 0640u);

    SQLite::Database raw(copy.string(), SQLite::OPEN_READONLY);
    EXPECT_EQ(raw.execAndGet("PRAGMA integrity_check").getString(), "ok");
    EXPECT_EQ(count(raw, "SELECT count(*) FROM epochs"), b.epochs);
    EXPECT_EQ(count(raw, "SELECT sum(n) FROM epoch_status_counts"), b.epochs);
    EXPECT_EQ(raw.execAndGet("PRAGMA journal_mode").getString(), "delete");
    // tlsmon's own reader opens it.
    auto reopened = EpochDatabase::open(copy, Mode::read_only);
    EXPECT_EQ(reopened.epochs().find_by_sha256(test::fake_sha256(0))->file_path, "/ingest/0.ptx");
}

TEST(DatabaseBackup, NeverOverwritesAndLeavesNoPartialFile) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    EpochDatabase::open(path, Mode::read_write);
    const auto existing = test::write_file(dir / "taken.sqlite", "keep me");
    try {
        backup_database(path, existing);
        FAIL() << "an existing file was overwritten";
    } catch (const StorageError& e) {
        EXPECT_NE(std::string(e.what()).find("exists already"), std::string::npos) << e.what();
    }
    EXPECT_EQ(test::read_file(existing), "keep me");

    const auto nowhere = dir / "no such folder" / "copy.sqlite";
    try {
        backup_database(path, nowhere);
        FAIL() << "a copy into a missing folder succeeded";
    } catch (const StorageError& e) {
        EXPECT_NE(std::string(e.what()).find(nowhere.string()), std::string::npos) << e.what();
    }
    EXPECT_THROW(backup_database(dir / "absent.sqlite", dir / "c.sqlite"), StorageError);
    EXPECT_FALSE(fs::exists(dir / "c.sqlite"));
    EXPECT_FALSE(fs::exists(dir / "c.sqlite.part"));
}

TEST(DatabaseBackup, AFolderGetsATimeStampedCopy) {
    test::TempDir dir;
    const auto path = dir / "site.sqlite";
    EpochDatabase::open(path, Mode::read_write);
    fs::create_directory(dir / "backups");
    const auto target = backup_destination(path, dir / "backups");
    EXPECT_EQ(target.parent_path(), dir / "backups");
    EXPECT_TRUE(target.filename().string().starts_with("site-20")) << target;
    EXPECT_EQ(target.extension(), ".sqlite");
    EXPECT_EQ(backup_destination(path, dir / "one.sqlite"), dir / "one.sqlite");
    backup_database(path, target);
    EXPECT_TRUE(fs::exists(target));
}

// A file written by a tlsmon that knew only 0001: before migrating it, the read-write open
// leaves a copy as it was beside it, and a system event names the copy.
TEST(DatabaseBackup, MigrationKeepsTheOldFileBesideIt) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    test::write_schema_1_database(path);
    { auto db = EpochDatabase::open(path, Mode::read_write); }
    std::vector<fs::path> copies;
    for (const auto& e : fs::directory_iterator(dir.path()))
        if (e.path().filename().string().starts_with("epochs.schema-1-"))
            copies.push_back(e.path());
    ASSERT_EQ(copies.size(), 1u);
    EXPECT_EQ(copies[0].extension(), ".sqlite");
    SQLite::Database old(copies[0].string(), SQLite::OPEN_READONLY);
    EXPECT_EQ(count(old, "SELECT max(version) FROM schema_migrations"), 1);
    EXPECT_EQ(count(old, "SELECT count(*) FROM epochs"), 1);
    EXPECT_FALSE(old.tableExists("epoch_stages"));  // 0003 not applied to the copy

    SQLite::Database migrated(path.string(), SQLite::OPEN_READONLY);
    SQLite::Statement event(migrated,
                            "SELECT message FROM system_events WHERE kind = 'schema_migrated'");
    ASSERT_TRUE(event.executeStep());
    const std::string message = event.getColumn(0).getString();
    EXPECT_NE(message.find("schema 1 migrated to " +
                           std::to_string(EpochDatabase::latest_schema_version())),
              std::string::npos)
        << message;
    EXPECT_NE(message.find(copies[0].string()), std::string::npos) << message;
    EXPECT_FALSE(event.executeStep());

    // Up to date now: opening again copies nothing.
    { auto db = EpochDatabase::open(path, Mode::read_write); }
    int after = 0;
    for (const auto& e : fs::directory_iterator(dir.path()))
        after += e.path().filename().string().starts_with("epochs.schema-");
    EXPECT_EQ(after, 1);
}

}  // namespace
}  // namespace tlsmon
