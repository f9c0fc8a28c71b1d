#pragma once
// File-level steps of ingest: the acquisition time of a scan file, and moving a file to the
// archive or to quarantine (with its <name>.reason.txt) without overwriting anything.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tlsmon {

// "YYYYMMDDTHHMMSSZ" anywhere in the file name (e.g. "pier_20260601T061500Z.ptx"), as UTC
// seconds; nullopt when absent or not a valid date.
std::optional<std::int64_t> time_from_file_name(const std::string& name);

// Modification time of the file, UTC seconds; nullopt if it cannot be read.
std::optional<std::int64_t> file_mtime(const std::filesystem::path& path);

// The first available source in `precedence` ("scan", "file_name", "mtime"); "scan" is the
// file's own header time (E57's acquisitionStart; the other formats have none). Falls back
// to mtime, then to now. `used` names the source taken.
std::int64_t acquisition_time(const std::filesystem::path& path,
                              const std::vector<std::string>& precedence, std::string& used);

// A free name for `name` in `folder`: name itself, else "stem.<tag>.ext", "stem.<tag>-2.ext".
std::filesystem::path free_name(const std::filesystem::path& folder, const std::string& name,
                                const std::string& tag);

// Renames `from` to `to` (same file system), else copies, syncs and removes. Throws Error.
void move_file(const std::filesystem::path& from, const std::filesystem::path& to);

// Writes "<file>.reason.txt" next to `file` (the quarantined copy). Returns false if it
// could not be written.
bool write_reason_file(const std::filesystem::path& file, const std::string& original,
                       const std::string& reason);

}  // namespace tlsmon
