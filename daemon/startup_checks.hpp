#pragma once
// What `tlsmon run` needs of the file system before it starts: the four folders usable (or
// creatable), the database and the log file openable. Checked without changing anything,
// so that `tlsmon check-config` rejects exactly what `run` would, and creates nothing.
#include <filesystem>
#include <string>
#include <vector>

#include "config/config.hpp"

namespace tlsmon {

// A configured folder that does not exist yet; `run` creates it.
struct MissingFolder {
    std::string key;  // "paths.ingest"
    std::filesystem::path path;
};

// Throws Error naming the key, the path and the system's reason for the first problem;
// returns the folders `run` will have to create.
std::vector<MissingFolder> check_startup(const Config& config);

// The notification channels' files (password, token, CA) that cannot be read now, one line
// each ("notify channel 'office': password_file /etc/tlsmon/smtp: No such file or
// directory"). Not fatal: each send reads them again, and says so in its failure.
std::vector<std::string> notify_file_problems(const NotifyConfig& notify);

// Creates `missing` (throws Error when that fails), logging a warning for each: a missing
// ingest folder is often a mistyped path, so it must not appear silently.
void create_missing_folders(const std::vector<MissingFolder>& missing);

}  // namespace tlsmon
