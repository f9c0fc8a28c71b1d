#pragma once
// Private to storage/: opening the SQLite connection of an EpochDatabase, per mode.
#include <chrono>
#include <filesystem>
#include <memory>

#include "storage/connection.hpp"

namespace tlsmon {

// Creates the file if needed, WAL and synchronous=FULL, migrated to the latest schema. A
// failure caused by a folder or file the user may not write is a StorageError naming it and
// the permission missing (file_access.hpp).
std::unique_ptr<Connection> open_read_write(const std::filesystem::path& path,
                                            std::chrono::milliseconds busy_timeout);

// Writes nothing, in any folder the user can read (see the .cpp for how); refuses a schema
// other than the latest.
std::unique_ptr<Connection> open_read_only(const std::filesystem::path& path,
                                           std::chrono::milliseconds busy_timeout);

}  // namespace tlsmon
