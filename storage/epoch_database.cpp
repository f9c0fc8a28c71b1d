// Opening the epoch database: connection settings, migrations, version check; the stores.
#include "storage/epoch_database.hpp"

#include <algorithm>
#include <chrono>

#include "storage/connection.hpp"
#include "storage/migrations.hpp"
#include "storage/schema_migrations.hpp"

namespace tlsmon {

void throw_storage(const Connection& c, const std::string& what) {
    throw StorageError(c.path.string() + ": " + what);
}

int EpochDatabase::latest_schema_version() {
    int latest = 0;
    for (const auto& m : schema_migrations()) latest = std::max(latest, m.version);
    return latest;
}

EpochDatabase EpochDatabase::open(const std::filesystem::path& path, Mode mode,
                                  std::chrono::milliseconds busy_timeout) {
    if (mode == Mode::read_only && !std::filesystem::exists(path)) {
        throw StorageError(path.string() + ": no such epoch database");
    }
    const int flags = mode == Mode::read_only ? SQLite::OPEN_READONLY
                                              : (SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    std::unique_ptr<Connection> c;
    try {
        c = std::make_unique<Connection>(
            path, mode, SQLite::Database(path, flags, static_cast<int>(busy_timeout.count())));
    } catch (const SQLite::Exception& e) {
        throw StorageError(path.string() + ": opening the epoch database: " + e.what(),
                           e.getErrorCode(), e.getExtendedErrorCode());
    }
    guarded(*c, "setting connection pragmas", [&] {
        c->db.exec("PRAGMA foreign_keys = ON");
        if (mode == Mode::read_write) {
            const std::string journal = c->db.execAndGet("PRAGMA journal_mode = WAL");
            if (journal != "wal") {
                throw SQLite::Exception("journal_mode is '" + journal + "', not 'wal'");
            }
            c->db.exec("PRAGMA synchronous = FULL");
        }
    });
    int version = applied_version(*c);
    check_not_newer(*c, version);
    if (mode == Mode::read_write) {
        migrate(*c, version);
        version = applied_version(*c);
        check_not_newer(*c, version);
    } else if (version < latest_schema_version()) {
        throw_storage(*c, "database schema version " + std::to_string(version) +
                              " is older than this tlsmon's (" +
                              std::to_string(latest_schema_version()) +
                              "); start the daemon once to migrate it");
    }
    c->version = version;
    return EpochDatabase(std::move(c));
}

EpochDatabase::EpochDatabase(std::unique_ptr<Connection> connection)
    : connection_(std::move(connection)),
      epochs_(*connection_),
      site_(*connection_),
      results_(*connection_),
      series_(*connection_),
      reference_cache_(*connection_),
      alarms_(*connection_),
      events_(*connection_) {}
EpochDatabase::EpochDatabase(EpochDatabase&&) noexcept = default;
EpochDatabase& EpochDatabase::operator=(EpochDatabase&&) noexcept = default;
EpochDatabase::~EpochDatabase() = default;

const std::filesystem::path& EpochDatabase::path() const {
    return connection_->path;
}
int EpochDatabase::schema_version() const {
    return connection_->version;
}

}  // namespace tlsmon
