#pragma once
// Private to storage/: why a user cannot open the epoch database for writing, in words an
// operator can act on (SQLite itself only says "unable to open database file").
#include <filesystem>
#include <optional>
#include <string>

namespace tlsmon {

// "folder /x/db is not writable by user tlsmon (uid 999)", or nullopt when the file, its
// folder and its -wal/-shm allow this process to write (the failure is something else).
std::optional<std::string> missing_write_permission(const std::filesystem::path& database);

// Whether this process may create files in the database's folder.
bool folder_writable(const std::filesystem::path& database);

// The process's effective user as "user NAME (uid N)".
std::string effective_user();

}  // namespace tlsmon
