#pragma once
// Private to storage/: what this process may do with the epoch database's files.
#include <filesystem>

namespace tlsmon {

// Whether this process may create files in the database's folder.
bool folder_writable(const std::filesystem::path& database);

}  // namespace tlsmon
