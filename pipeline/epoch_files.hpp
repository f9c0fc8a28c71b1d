#pragma once
// Moving an epoch's file to the archive or to quarantine (with its <name>.reason.txt)
// without overwriting anything.
#include <filesystem>
#include <string>

namespace tlsmon {

// A free name for `name` in `folder`: name itself, else "stem.<tag>.ext", "stem.<tag>-2.ext".
std::filesystem::path free_name(const std::filesystem::path& folder, const std::string& name,
                                const std::string& tag);

// Renames `from` to `to` (same file system), else copies, syncs and removes. A symbolic
// link is renamed as a link, never read through: to another file system it is not moved
// (Error). Throws Error.
void move_file(const std::filesystem::path& from, const std::filesystem::path& to);

// Writes "<file>.reason.txt" next to `file` (the quarantined copy): two lines, "file:" and
// "reason:", control characters escaped (core/text_escape.hpp). Returns false if it could
// not be written.
bool write_reason_file(const std::filesystem::path& file, const std::string& original,
                       const std::string& reason);

}  // namespace tlsmon
