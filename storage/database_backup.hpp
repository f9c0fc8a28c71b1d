#pragma once
// A consistent copy of an epoch database while the daemon writes to it, through SQLite's
// online backup API (sqlite.org/backup.html): `tlsmon backup DEST`, and the copy taken
// before a schema migration (docs/backup.md).
#include <cstdint>
#include <filesystem>

namespace tlsmon {

struct DatabaseBackup {
    std::filesystem::path path;  // the copy written
    int schema_version = 0;      // of the copy (the source's at the snapshot)
    std::int64_t epochs = 0;     // epochs in the copy
    std::int64_t bytes = 0;      // size of the copy
};

// Copies `source` as it was at one instant (one read transaction: the daemon's commits
// during the copy are not in it, and do not restart it) to `destination`, a file that must
// not exist yet. The copy is written beside it as "<destination>.part", checked
// (PRAGMA quick_check), made durable (fsync) and then renamed, so `destination` is either
// absent or complete; it is one file (rollback journal, no -wal) with the source's
// permission bits. Throws StorageError naming the file and the step that failed; a partial
// copy is removed.
DatabaseBackup backup_database(const std::filesystem::path& source,
                               const std::filesystem::path& destination);

// `destination` itself, or, for an existing folder, "<folder>/<database stem>-<UTC time as
// YYYYMMDDTHHMMSSZ>.sqlite".
std::filesystem::path backup_destination(const std::filesystem::path& source,
                                         const std::filesystem::path& destination);

// Where the copy before migrating a schema-`version` file goes: beside it, as
// "<stem>.schema-<version>-<UTC time>.sqlite".
std::filesystem::path migration_backup_path(const std::filesystem::path& source, int version);

}  // namespace tlsmon
