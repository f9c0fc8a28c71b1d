// Opening the SQLite connection of an EpochDatabase: a writer creates, migrates and says
// which permission is missing; a reader writes nothing and reads from a folder it cannot
// write.
#include "storage/open_connection.hpp"

#include <sqlite3.h>

#include <cctype>
#include <cstdio>
#include <initializer_list>
#include <mutex>

#include "storage/database_backup.hpp"
#include "storage/event_log.hpp"
#include "storage/file_access.hpp"
#include "storage/migrations.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

using Mode = EpochDatabase::Mode;

// Once per process, before SQLite initialises: each connection is used by one thread at a
// time (epoch_database.hpp), so the multi-thread mode drops the per-connection mutex, and
// without the memory statistics every allocation skips a process-wide mutex that the
// dashboard's threads, each reading on its own connection, would otherwise queue on. A
// call after SQLite was initialised (by another user of the library) is refused by SQLite
// and changes nothing, which is safe.
void configure_sqlite() {
    static std::once_flag once;
    std::call_once(once, [] {
        sqlite3_config(SQLITE_CONFIG_MULTITHREAD);
        sqlite3_config(SQLITE_CONFIG_MEMSTATUS, 0);
    });
}

std::unique_ptr<Connection> connect(const fs::path& path, const std::string& filename, Mode mode,
                                    int flags, std::chrono::milliseconds busy_timeout) {
    configure_sqlite();
    try {
        return std::make_unique<Connection>(
            path, mode, SQLite::Database(filename, flags, static_cast<int>(busy_timeout.count())));
    } catch (const SQLite::Exception& e) {
        throw StorageError(path.string() + ": opening the epoch database: " + e.what(),
                           e.getErrorCode(), e.getExtendedErrorCode());
    }
}

bool has_primary_code(const StorageError& e, std::initializer_list<int> codes) {
    for (int code : codes) {
        if ((e.sqlite_code() & 0xff) == code || (e.extended_code() & 0xff) == code) return true;
    }
    return false;
}

// A file: URI (sqlite.org/uri.html) for `path` with `query`; every byte but the unreserved
// ones and '/' percent-encoded, so '?', '#' and '%' in a folder name stay part of the path.
std::string file_uri(const fs::path& path, const std::string& query) {
    std::string out = "file:";
    for (unsigned char ch : fs::absolute(path).string()) {
        if (std::isalnum(ch) || ch == '/' || ch == '-' || ch == '_' || ch == '.' || ch == '~') {
            out += static_cast<char>(ch);
        } else {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", ch);
            out += hex;
        }
    }
    return out + "?" + query;
}

// True when every committed transaction is in the main file: no -wal, or an empty one.
bool wal_absent_or_empty(const fs::path& path) {
    std::error_code ec;
    const fs::path wal = path.string() + "-wal";
    const auto size = fs::file_size(wal, ec);
    if (!ec) return size == 0;
    return !fs::exists(wal, ec) && !ec;
}

void check_version_for_reading(Connection& c, int version) {
    check_not_newer(c, version);
    if (version < EpochDatabase::latest_schema_version()) {
        throw_storage(c, "database schema version " + std::to_string(version) +
                             " is older than this tlsmon's (" +
                             std::to_string(EpochDatabase::latest_schema_version()) +
                             "); start the daemon once to migrate it");
    }
}

// A file with data is copied as it was before its first migration, beside it, and the copy
// named in a system event (docs/backup.md, "Schema migrations"): the way back to the older
// tlsmon. Once per process at a time (the daemon's services open at once); a second process
// migrating at the same instant at worst makes a second copy. When the copy cannot be made
// (a full disk) the migration does not run: the StorageError says why.
void migrate_after_backup(Connection& c) {
    static std::mutex one_at_a_time;
    const std::lock_guard lock(one_at_a_time);
    const int version = applied_version(c);
    if (version >= EpochDatabase::latest_schema_version()) return;  // another thread did it
    const auto backup = backup_database(c.path, migration_backup_path(c.path, version));
    migrate(c, version);
    EventLog(c).record({now_utc(), "info", "schema_migrated",
                        "schema " + std::to_string(version) + " migrated to " +
                            std::to_string(EpochDatabase::latest_schema_version()) +
                            "; the database as it was before: " + backup.path.string() +
                            " (docs/backup.md)",
                        std::nullopt});
}

std::unique_ptr<Connection> open_and_migrate(const fs::path& path,
                                             std::chrono::milliseconds busy_timeout) {
    auto c = connect(path, path.string(), Mode::read_write,
                     SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE, busy_timeout);
    // SQLite quietly opens a file it may not write read-only; the daemon would then start
    // and fail at its first write. Refuse it here, where the permission can be named.
    if (sqlite3_db_readonly(c->db.getHandle(), "main") == 1) {
        throw StorageError(path.string() + ": opening the epoch database: opened read-only",
                           SQLITE_READONLY, SQLITE_READONLY);
    }
    guarded(*c, "setting connection pragmas", [&] {
        c->db.exec("PRAGMA foreign_keys = ON");
        // A new file is made incremental, so the retention policy's freed pages can go back
        // to the file system in small steps (docs/retention.md). Only a new one: on an
        // existing file the pragma would wait for another connection's write lock.
        if (c->db.execAndGet("PRAGMA page_count").getInt64() == 0) {
            c->db.exec("PRAGMA auto_vacuum = INCREMENTAL");
        }
        const std::string journal = c->db.execAndGet("PRAGMA journal_mode = WAL");
        if (journal != "wal") {
            throw SQLite::Exception("journal_mode is '" + journal + "', not 'wal'");
        }
        c->db.exec("PRAGMA synchronous = FULL");
    });
    int version = applied_version(*c);
    check_not_newer(*c, version);
    if (version > 0 && version < EpochDatabase::latest_schema_version()) {
        migrate_after_backup(*c);
    } else {
        migrate(*c, version);
    }
    version = applied_version(*c);
    check_not_newer(*c, version);
    c->version = version;
    return c;
}

}  // namespace

std::unique_ptr<Connection> open_read_write(const fs::path& path,
                                            std::chrono::milliseconds busy_timeout) {
    try {
        return open_and_migrate(path, busy_timeout);
    } catch (const StorageError& e) {
        // SQLite says only "unable to open database file" or "attempt to write a readonly
        // database"; name the folder or file and the permission instead. Checked after the
        // failure, so a successful open costs nothing and no check can disagree with it.
        if (!has_primary_code(e, {SQLITE_CANTOPEN, SQLITE_READONLY, SQLITE_PERM, SQLITE_IOERR})) {
            throw;
        }
        const auto why = missing_write_permission(path);
        if (!why) throw;
        throw StorageError(*why + " (" + e.what() + ")", e.sqlite_code(), e.extended_code());
    }
}

// A reader first opens as SQLite intends (read-only). Since SQLite 3.22 that reads a WAL
// database in a folder the user cannot write as long as the -wal and -shm files exist: while
// the daemon runs, or after it was killed (SQLite then reads the -shm read-only, or rebuilds
// the index in private memory from the -wal). After the daemon stopped cleanly they are gone
// (the last connection removes them), SQLite would have to create them, and the first read
// fails with SQLITE_READONLY_DIRECTORY. Only in that case, and only when there is no -wal or
// an empty one, i.e. every committed transaction is in the main file, the reader opens with
// immutable=1: no locks, no -shm, the main file read as it is.
// immutable=1 is exact while no writer checkpoints into the main file; for that a daemon
// would have to start, create the -wal, fill it and checkpoint within the read of one
// command (milliseconds; SQLite checkpoints at 1000 pages or at close), and even then a
// reader gets a wrong answer or SQLITE_CORRUPT for that command, never a changed database
// (an immutable open cannot write). A long-lived reader must therefore not rely on this: it
// belongs where the folder is writable (the daemon's user). A reader that cannot read the
// -shm of a running daemon fails with SQLite's error rather than read the main file, which
// would miss the commits still in the -wal.
std::unique_ptr<Connection> open_read_only(const fs::path& path,
                                           std::chrono::milliseconds busy_timeout) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw StorageError(path.string() + ": no such epoch database");
    // No pragma at all: journal_mode would write, and foreign keys matter only to writes.
    auto c = connect(path, path.string(), Mode::read_only, SQLite::OPEN_READONLY, busy_timeout);
    int version = 0;
    try {
        version = applied_version(*c);  // the first read opens the WAL index
    } catch (const StorageError& e) {
        if (!has_primary_code(e, {SQLITE_READONLY, SQLITE_CANTOPEN}) || folder_writable(path) ||
            !wal_absent_or_empty(path)) {
            throw;
        }
        c = connect(path, file_uri(path, "immutable=1"), Mode::read_only,
                    SQLite::OPEN_READONLY | SQLite::OPEN_URI, busy_timeout);
        version = applied_version(*c);
    }
    check_version_for_reading(*c, version);
    c->version = version;
    return c;
}

}  // namespace tlsmon
