// The online backup of an epoch database (database_backup.hpp).
#include "storage/database_backup.hpp"

#include <SQLiteCpp/Backup.h>
#include <SQLiteCpp/SQLiteCpp.h>
#include <fcntl.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "core/utc_time.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

// Pages per step: between steps the source's lock is released, but the read transaction
// below keeps its snapshot, so a commit of the daemon in between neither blocks on the copy
// nor restarts it.
constexpr int kPagesPerStep = 4096;

[[noreturn]] void fail(const fs::path& file, const std::string& step, const std::string& why,
                       int code = 0, int extended = 0) {
    throw StorageError(file.string() + ": " + step + ": " + why, code, extended);
}

// fsync of a file or folder; a failure is the disk's (an I/O error), named with the file.
void sync_path(const fs::path& path, int flags) {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
        const int e = errno;
        if (fd >= 0) ::close(fd);
        fail(path, "making the backup durable", std::strerror(e), SQLITE_IOERR, SQLITE_IOERR);
    }
    ::close(fd);
}

// The empty .part file, created exclusively with the source's permission bits (the database
// holds the dashboard's user records: a copy must not be more readable than the original).
void create_part(const fs::path& source, const fs::path& part) {
    struct stat st {};
    const mode_t mode = ::stat(source.c_str(), &st) == 0 ? (st.st_mode & 0777) : 0600;
    const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
    if (fd < 0) {
        const int e = errno;
        fail(part, "creating the backup", std::strerror(e),
             e == ENOSPC ? SQLITE_FULL : SQLITE_CANTOPEN, 0);
    }
    ::fchmod(fd, mode);  // exact, whatever the umask
    ::close(fd);
}

DatabaseBackup copy_snapshot(const fs::path& source, const fs::path& part) {
    SQLite::Database src(source.string(), SQLite::OPEN_READONLY, 5000);
    // The snapshot: a read transaction held for the whole copy (WAL: writers go on).
    src.exec("BEGIN");
    const int version =
        src.tableExists("schema_migrations")
            ? src.execAndGet("SELECT coalesce(max(version), 0) FROM schema_migrations").getInt()
            : 0;
    {
        SQLite::Database dst(part.string(), SQLite::OPEN_READWRITE, 5000);
        SQLite::Backup backup(dst, src);
        for (;;) {
            const int rc = backup.executeStep(kPagesPerStep);
            if (rc == SQLITE_DONE) break;
            if (rc != SQLITE_OK && rc != SQLITE_BUSY && rc != SQLITE_LOCKED) {
                fail(part, "copying pages", sqlite3_errstr(rc), rc, rc);
            }
            if (rc != SQLITE_OK) sqlite3_sleep(50);
        }
        // One self-contained file: no -wal beside the copy.
        dst.exec("PRAGMA journal_mode = DELETE");
        const std::string check = dst.execAndGet("PRAGMA quick_check").getString();
        if (check != "ok") fail(part, "checking the copy", "quick_check: " + check);
    }
    src.exec("COMMIT");
    DatabaseBackup b;
    b.schema_version = version;
    {
        SQLite::Database dst(part.string(), SQLite::OPEN_READONLY);
        if (dst.tableExists("epochs"))
            b.epochs = dst.execAndGet("SELECT count(*) FROM epochs").getInt64();
    }
    return b;
}

// Now as 20261202T200000Z: sorts by time, no ':' for the file systems and tools that mind.
std::string utc_stamp() {
    std::string stamp = format_utc(now_utc());
    stamp.erase(
        std::remove_if(stamp.begin(), stamp.end(), [](char ch) { return ch == '-' || ch == ':'; }),
        stamp.end());
    return stamp;
}

}  // namespace

fs::path backup_destination(const fs::path& source, const fs::path& destination) {
    std::error_code ec;
    if (!fs::is_directory(destination, ec)) return destination;
    return destination / (source.stem().string() + "-" + utc_stamp() + ".sqlite");
}

fs::path migration_backup_path(const fs::path& source, int version) {
    return source.parent_path() / (source.stem().string() + ".schema-" + std::to_string(version) +
                                   "-" + utc_stamp() + ".sqlite");
}

DatabaseBackup backup_database(const fs::path& source, const fs::path& destination) {
    std::error_code ec;
    if (!fs::exists(source, ec)) fail(source, "backing up", "no such epoch database");
    if (fs::exists(destination, ec) || fs::is_symlink(destination, ec)) {
        fail(destination, "backing up " + source.string(), "exists already; not overwritten");
    }
    const fs::path part = destination.string() + ".part";
    fs::remove(part, ec);  // left by an interrupted backup
    create_part(source, part);
    try {
        DatabaseBackup b = copy_snapshot(source, part);
        sync_path(part, O_RDONLY);
        fs::rename(part, destination);
        const fs::path folder = destination.parent_path().empty() ? "." : destination.parent_path();
        sync_path(folder, O_RDONLY | O_DIRECTORY);
        b.path = destination;
        b.bytes = static_cast<std::int64_t>(fs::file_size(destination));
        return b;
    } catch (const SQLite::Exception& e) {
        fs::remove(part, ec);
        fail(source, "backing up to " + destination.string(), e.what(), e.getErrorCode(),
             e.getExtendedErrorCode());
    } catch (const fs::filesystem_error& e) {
        fs::remove(part, ec);
        fail(destination, "backing up " + source.string(), e.code().message());
    } catch (...) {
        fs::remove(part, ec);
        throw;
    }
}

}  // namespace tlsmon
