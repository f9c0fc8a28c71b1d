#pragma once
// The daemon's folders must be apart: a scan archived into the ingest folder (or a folder
// inside it) is found again as a new file and removed as a duplicate of itself; the
// database inside a folder whose files are moved or deleted is lost with them. Ingest,
// archive and quarantine may neither be one folder nor lie inside one another, and the
// database may lie in none of them (its folder may hold them, as the default site does).
#include <optional>
#include <string>

#include "config/config.hpp"

namespace tlsmon {

struct FolderOverlap {
    std::string key;   // "archive": the key reported, in [paths]
    std::string what;  // "is paths.ingest (/site/ingest) ..."
};

// On the paths as written (resolved against the configuration's folder).
std::optional<FolderOverlap> folders_overlap(const PathsConfig& paths);

// On disk: links followed, and an existing folder compared by device and inode with the
// other folders and each of their existing parents (a bind mount, a symbolic link).
std::optional<FolderOverlap> folders_overlap_on_disk(const PathsConfig& paths);

}  // namespace tlsmon
