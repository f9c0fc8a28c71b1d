// Migrations: applied in order and recorded, reopen idempotent, newer databases refused.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include "fake_sha256.hpp"
#include "schema_1_database.hpp"
#include "storage/epoch_database.hpp"
#include "storage/schema_migrations.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

TEST(Migrations, EmbeddedInVersionOrder) {
    const auto migrations = schema_migrations();
    ASSERT_GE(migrations.size(), 1u);
    EXPECT_EQ(migrations[0].version, 1);
    EXPECT_STREQ(migrations[0].name, "0001_initial");
    EXPECT_NE(std::string(migrations[0].sql).find("CREATE TABLE epochs"), std::string::npos);
    for (std::size_t i = 1; i < migrations.size(); ++i) {
        EXPECT_LT(migrations[i - 1].version, migrations[i].version);
    }
    EXPECT_EQ(EpochDatabase::latest_schema_version(), migrations.back().version);
}

TEST(Migrations, AppliedAndRecordedOnCreate) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        EXPECT_EQ(db.schema_version(), EpochDatabase::latest_schema_version());
    }
    SQLite::Database raw(path.string(), SQLite::OPEN_READONLY);
    SQLite::Statement s(raw, "SELECT version, name FROM schema_migrations ORDER BY version");
    std::size_t i = 0;
    for (const auto& m : schema_migrations()) {
        ASSERT_TRUE(s.executeStep()) << "migration " << m.name << " not recorded";
        EXPECT_EQ(s.getColumn(0).getInt(), m.version);
        EXPECT_EQ(s.getColumn(1).getString(), m.name);
        ++i;
    }
    EXPECT_FALSE(s.executeStep());
    EXPECT_EQ(i, schema_migrations().size());
    for (const char* table :
         {"stations", "epochs", "reference_epoch", "registrations", "target_observations", "zones",
          "quantities", "zone_results", "core_point_arrays", "alarm_rules", "alarm_states",
          "alarm_events", "system_events", "reference_cache"}) {
        EXPECT_TRUE(raw.tableExists(table)) << table;
    }
    EXPECT_EQ(raw.execAndGet("PRAGMA journal_mode").getString(), "wal");
}

TEST(Migrations, ReopenIsIdempotentAndKeepsData) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        db.epochs().insert({test::fake_sha256(1), 1000, "/ingest/a.ptx", 10, std::nullopt});
    }
    for (int i = 0; i < 2; ++i) {
        auto db = EpochDatabase::open(path, Mode::read_write);
        EXPECT_EQ(db.schema_version(), EpochDatabase::latest_schema_version());
        ASSERT_EQ(db.epochs().pending().size(), 1u);
    }
    SQLite::Database raw(path.string(), SQLite::OPEN_READONLY);
    EXPECT_EQ(raw.execAndGet("SELECT count(*) FROM schema_migrations").getInt(),
              static_cast<int>(schema_migrations().size()));
}

// A file written by a tlsmon that knew only 0001 gets the later migrations at the next
// read_write open, its epochs kept; a reader refuses it until then.
TEST(Migrations, OlderDatabaseIsMigratedKeepingData) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    test::write_schema_1_database(path);
    EXPECT_THROW(EpochDatabase::open(path, Mode::read_only), StorageError);
    auto db = EpochDatabase::open(path, Mode::read_write);
    EXPECT_EQ(db.schema_version(), EpochDatabase::latest_schema_version());
    EXPECT_GE(db.schema_version(), 2);
    EXPECT_EQ(db.epochs().find_by_sha256(test::fake_sha256(7))->file_path, "/ingest/a.ptx");
    EXPECT_EQ(db.reference_cache().load({"s", test::fake_sha256(7), "p", 1}).status,
              CacheLookup::missing);
}

TEST(Migrations, NewerDatabaseIsRefused) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    EpochDatabase::open(path, Mode::read_write);
    const int newer = EpochDatabase::latest_schema_version() + 1;
    {
        SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE);
        SQLite::Statement s(raw, "INSERT INTO schema_migrations VALUES (?, 'future', 0)");
        s.bind(1, newer);
        s.exec();
    }
    for (auto mode : {Mode::read_write, Mode::read_only}) {
        try {
            EpochDatabase::open(path, mode);
            FAIL() << "a version " << newer << " database was opened";
        } catch (const StorageError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(path.string()), std::string::npos) << what;
            EXPECT_NE(what.find("schema version " + std::to_string(newer) + " is newer"),
                      std::string::npos)
                << what;
            EXPECT_FALSE(e.disk_full());
        }
    }
}

TEST(Migrations, ReadOnlyNeverCreatesOrMigrates) {
    test::TempDir dir;
    const auto path = dir / "missing.sqlite";
    EXPECT_THROW(EpochDatabase::open(path, Mode::read_only), StorageError);
    EXPECT_FALSE(std::filesystem::exists(path));
    {  // an empty SQLite file (not yet migrated) is not silently migrated by a reader
        SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
        raw.exec("CREATE TABLE other (x)");
    }
    EXPECT_THROW(EpochDatabase::open(path, Mode::read_only), StorageError);
    SQLite::Database raw(path.string(), SQLite::OPEN_READONLY);
    EXPECT_FALSE(raw.tableExists("epochs"));
}

TEST(Migrations, NotADatabaseIsAClearError) {
    test::TempDir dir;
    const auto path = dir / "garbage.sqlite";
    test::write_file(path, std::string(4096, 'x'));
    try {
        EpochDatabase::open(path, Mode::read_write);
        FAIL() << "a text file opened as a database";
    } catch (const StorageError& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
}

// The counters of 0012 start from the epochs already there and follow every insert, status
// change and delete: after each, they equal a count of the epochs table itself.
TEST(Migrations, EpochStatusCountsFollowEveryChange) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    const auto counters_match_epochs = [&](SQLite::Database& raw) {
        const char* sql =
            "SELECT count(*) FROM epoch_status_counts c WHERE c.n <>"
            " (SELECT count(*) FROM epochs e WHERE e.status = c.status)";
        return raw.execAndGet(sql).getInt() == 0 &&
               raw.execAndGet("SELECT sum(n) FROM epoch_status_counts").getInt() ==
                   raw.execAndGet("SELECT count(*) FROM epochs").getInt();
    };
    {  // a database at 0011 with epochs in three states
        SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
        raw.exec(
            "CREATE TABLE schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT NULL,"
            " applied INTEGER NOT NULL)");
        for (const auto& m : schema_migrations()) {
            if (m.version > 11) break;
            raw.exec(m.sql);
            SQLite::Statement s(raw, "INSERT INTO schema_migrations VALUES (?, ?, 0)");
            s.bind(1, m.version);
            s.bind(2, m.name);
            s.exec();
        }
        int i = 0;
        for (const char* status : {"done", "done", "done", "rejected", "pending"}) {
            ++i;
            raw.exec(
                "INSERT INTO epochs (sha256, acquired, discovered, updated, file_path,"
                " file_size, status) VALUES ('" +
                test::fake_sha256(i) + "', " + std::to_string(100 * i) + ", 0, 0, 'f', 1, '" +
                status + "')");
        }
    }
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        const auto s = db.series().status_summary();
        EXPECT_EQ(s.epochs_by_status.at(EpochStatus::done), 3);
        EXPECT_EQ(s.epochs_by_status.at(EpochStatus::rejected), 1);
        EXPECT_EQ(s.epochs_by_status.at(EpochStatus::pending), 1);
        EXPECT_EQ(s.epochs_by_status.at(EpochStatus::failed), 0);
        EXPECT_EQ(s.backlog, 1);
        db.epochs().insert({test::fake_sha256(9), 900, "/ingest/b.ptx", 10, std::nullopt});
        EXPECT_EQ(db.series().status_summary().epochs_by_status.at(EpochStatus::pending), 2);
    }
    SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE);
    EXPECT_TRUE(counters_match_epochs(raw));
    raw.exec("UPDATE epochs SET status = 'processing' WHERE status = 'pending'");
    EXPECT_EQ(
        raw.execAndGet("SELECT n FROM epoch_status_counts WHERE status = 'processing'").getInt(),
        2);
    EXPECT_TRUE(counters_match_epochs(raw));
    raw.exec("UPDATE epochs SET status = 'failed', reason = 'x' WHERE status = 'processing'");
    raw.exec("UPDATE epochs SET reason = 'again' WHERE status = 'failed'");  // no status change
    EXPECT_TRUE(counters_match_epochs(raw));
    raw.exec("DELETE FROM epochs WHERE status = 'done' AND acquired < 250");
    EXPECT_EQ(raw.execAndGet("SELECT n FROM epoch_status_counts WHERE status = 'done'").getInt(),
              1);
    EXPECT_TRUE(counters_match_epochs(raw));
}

}  // namespace
}  // namespace tlsmon
