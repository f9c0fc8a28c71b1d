#pragma once
// The acquisition time of a scan file, as ingest records it with the new epoch.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "config/time_source.hpp"

namespace tlsmon {

// "YYYYMMDDTHHMMSSZ" anywhere in the file name (e.g. "pier_20260601T061500Z.ptx"), as UTC
// seconds; nullopt when absent or not a valid date.
std::optional<std::int64_t> time_from_file_name(const std::string& name);

// Modification time of the file, UTC seconds; nullopt if it cannot be read.
std::optional<std::int64_t> file_mtime(const std::filesystem::path& path);

// The first available source in `precedence`. Falls back to mtime, then to now. `used`
// names the source taken, for the log.
std::int64_t acquisition_time(const std::filesystem::path& path,
                              const std::vector<TimeSource>& precedence, std::string& used);

}  // namespace tlsmon
