// Opening the epoch database: connection settings, numbered migrations, version check.
#include "storage/epoch_database.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <chrono>

#include "storage/epoch_database_impl.hpp"
#include "storage/schema_migrations.hpp"

namespace tlsmon {

StorageError::StorageError(const std::string& what, int sqlite_code, int extended_code)
    : Error(what), sqlite_code_(sqlite_code), extended_code_(extended_code) {}

bool StorageError::disk_full() const noexcept {
    // Primary codes are the low byte of extended codes (sqlite.org/rescode.html).
    for (int code : {sqlite_code_, extended_code_}) {
        if (code <= 0) continue;
        const int primary = code & 0xff;
        if (primary == SQLITE_FULL || primary == SQLITE_IOERR) return true;
    }
    return false;
}

bool StorageError::busy() const noexcept {
    for (int code : {sqlite_code_, extended_code_}) {
        if (code <= 0) continue;
        const int primary = code & 0xff;
        if (primary == SQLITE_BUSY || primary == SQLITE_LOCKED) return true;
    }
    return false;
}

std::string_view to_string(EpochStatus status) {
    switch (status) {
        case EpochStatus::pending:
            return "pending";
        case EpochStatus::processing:
            return "processing";
        case EpochStatus::done:
            return "done";
        case EpochStatus::failed:
            return "failed";
        case EpochStatus::rejected:
            return "rejected";
    }
    return "?";
}

EpochStatus epoch_status_from_string(std::string_view name) {
    for (auto s : {EpochStatus::pending, EpochStatus::processing, EpochStatus::done,
                   EpochStatus::failed, EpochStatus::rejected}) {
        if (to_string(s) == name) return s;
    }
    throw StorageError("unknown epoch status '" + std::string(name) + "'");
}

void throw_storage(const EpochDatabase::Impl& impl, const std::string& what) {
    throw StorageError(impl.path.string() + ": " + what);
}

int EpochDatabase::latest_schema_version() {
    int latest = 0;
    for (const auto& m : schema_migrations()) latest = std::max(latest, m.version);
    return latest;
}

namespace {

int applied_version(EpochDatabase::Impl& impl) {
    return guarded(impl, "reading schema_migrations", [&] {
        if (!impl.db.tableExists("schema_migrations")) return 0;
        return impl.db.execAndGet("SELECT coalesce(max(version), 0) FROM schema_migrations")
            .getInt();
    });
}

void check_not_newer(EpochDatabase::Impl& impl, int version) {
    const int latest = EpochDatabase::latest_schema_version();
    if (version > latest) {
        throw_storage(impl, "database schema version " + std::to_string(version) +
                                " is newer than this tlsmon knows (" + std::to_string(latest) +
                                "); use the tlsmon that wrote it or a newer one");
    }
}

// Each migration in its own IMMEDIATE transaction, re-checking the version under the write
// lock so two processes starting at once do not apply a migration twice.
// Nothing is written (no write lock taken) when the file is already up to date, so a
// restart does not wait for another writer.
void migrate(EpochDatabase::Impl& impl, int applied) {
    if (applied >= EpochDatabase::latest_schema_version()) return;
    guarded(impl, "creating schema_migrations", [&] {
        impl.db.exec(
            "CREATE TABLE IF NOT EXISTS schema_migrations ("
            " version INTEGER PRIMARY KEY, name TEXT NOT NULL, applied INTEGER NOT NULL)");
    });
    for (const auto& m : schema_migrations()) {
        if (m.version <= applied) continue;
        const std::string context = std::string("applying migration ") + m.name;
        guarded(impl, context.c_str(), [&] {
            SQLite::Transaction tx(impl.db, SQLite::TransactionBehavior::IMMEDIATE);
            SQLite::Statement done(impl.db, "SELECT 1 FROM schema_migrations WHERE version = ?");
            done.bind(1, m.version);
            if (done.executeStep()) return;
            impl.db.exec(m.sql);
            SQLite::Statement record(
                impl.db, "INSERT INTO schema_migrations (version, name, applied) VALUES (?,?,?)");
            record.bind(1, m.version);
            record.bind(2, m.name);
            record.bind(3, static_cast<std::int64_t>(now_utc()));
            record.exec();
            tx.commit();
        });
    }
}

}  // namespace

EpochDatabase EpochDatabase::open(const std::filesystem::path& path, Mode mode,
                                  std::chrono::milliseconds busy_timeout) {
    if (mode == Mode::read_only && !std::filesystem::exists(path)) {
        throw StorageError(path.string() + ": no such epoch database");
    }
    const int flags = mode == Mode::read_only ? SQLite::OPEN_READONLY
                                              : (SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    std::unique_ptr<Impl> impl;
    try {
        impl = std::make_unique<Impl>(
            path, mode, SQLite::Database(path, flags, static_cast<int>(busy_timeout.count())));
    } catch (const SQLite::Exception& e) {
        throw StorageError(path.string() + ": opening the epoch database: " + e.what(),
                           e.getErrorCode(), e.getExtendedErrorCode());
    }
    guarded(*impl, "setting connection pragmas", [&] {
        impl->db.exec("PRAGMA foreign_keys = ON");
        if (mode == Mode::read_write) {
            const std::string journal = impl->db.execAndGet("PRAGMA journal_mode = WAL");
            if (journal != "wal") {
                throw SQLite::Exception("journal_mode is '" + journal + "', not 'wal'");
            }
            impl->db.exec("PRAGMA synchronous = FULL");
        }
    });
    int version = applied_version(*impl);
    check_not_newer(*impl, version);
    if (mode == Mode::read_write) {
        migrate(*impl, version);
        version = applied_version(*impl);
        check_not_newer(*impl, version);
    } else if (version < latest_schema_version()) {
        throw_storage(*impl, "database schema version " + std::to_string(version) +
                                 " is older than this tlsmon's (" +
                                 std::to_string(latest_schema_version()) +
                                 "); start the daemon once to migrate it");
    }
    impl->version = version;
    return EpochDatabase(std::move(impl));
}

EpochDatabase::EpochDatabase(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EpochDatabase::EpochDatabase(EpochDatabase&&) noexcept = default;
EpochDatabase& EpochDatabase::operator=(EpochDatabase&&) noexcept = default;
EpochDatabase::~EpochDatabase() = default;

const std::filesystem::path& EpochDatabase::path() const {
    return impl_->path;
}
int EpochDatabase::schema_version() const {
    return impl_->version;
}

const char* const kEpochColumns =
    "id, sha256, acquired, discovered, updated, file_path, file_size, station_id, status, "
    "reason, point_count, read_ms, register_ms, analyse_ms, total_ms, archive_path";

Epoch read_epoch(SQLite::Statement& s) {
    Epoch e;
    e.id = s.getColumn(0).getInt64();
    e.sha256 = s.getColumn(1).getString();
    e.acquired = s.getColumn(2).getInt64();
    e.discovered = s.getColumn(3).getInt64();
    e.updated = s.getColumn(4).getInt64();
    e.file_path = s.getColumn(5).getString();
    e.file_size = s.getColumn(6).getInt64();
    e.station = optional_int64(s.getColumn(7));
    e.status = epoch_status_from_string(s.getColumn(8).getString());
    e.reason = s.getColumn(9).getString();
    e.point_count = optional_int64(s.getColumn(10));
    e.timings.read_ms = optional_double(s.getColumn(11));
    e.timings.register_ms = optional_double(s.getColumn(12));
    e.timings.analyse_ms = optional_double(s.getColumn(13));
    e.timings.total_ms = optional_double(s.getColumn(14));
    e.archive_path = optional_string(s.getColumn(15));
    return e;
}

}  // namespace tlsmon
