#include "daemon/startup_checks.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "config/folder_overlap.hpp"
#include "core/error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

// access(2) for the real user: the daemon's own permissions, not the file mode bits (root
// may write anywhere but on a read-only file system).
void require_access(const std::string& key, const fs::path& path, int mode,
                    const std::string& what) {
    if (::access(path.c_str(), mode) != 0) {
        throw Error(key + ": " + path.string() + ": cannot " + what + ": " + std::strerror(errno));
    }
}

fs::file_status status_of(const fs::path& path) {
    std::error_code ec;
    return fs::status(path, ec);  // not_found when missing or unreachable
}

// The nearest existing folder above `path`, which must let us create what is missing.
void require_creatable(const std::string& key, const fs::path& path) {
    fs::path above = path.parent_path();
    while (!above.empty() && !fs::exists(status_of(above)) && above != above.root_path()) {
        above = above.parent_path();
    }
    if (above.empty()) above = ".";
    if (!fs::is_directory(status_of(above))) {
        throw Error(key + ": cannot create " + path.string() + ": " + above.string() +
                    " is not a folder");
    }
    if (::access(above.c_str(), W_OK | X_OK) != 0) {
        throw Error(key + ": cannot create " + path.string() + " in " + above.string() + ": " +
                    std::strerror(errno));
    }
}

// A folder the daemon reads (`mode` R_OK) and/or writes (W_OK) in.
void check_folder(const std::string& key, const fs::path& path, int mode,
                  std::vector<MissingFolder>& missing) {
    const fs::file_status st = status_of(path);
    if (!fs::exists(st)) {
        require_creatable(key, path);
        for (const auto& m : missing) {
            if (m.path == path) return;  // two keys name the same folder
        }
        missing.push_back({key, path});
        return;
    }
    if (!fs::is_directory(st)) throw Error(key + ": " + path.string() + " is not a folder");
    require_access(key, path, mode | X_OK,
                   mode & W_OK ? "write files in the folder" : "read the folder");
}

// A file the daemon opens for writing (created, with its folders, when missing).
void check_writable_file(const std::string& key, const fs::path& path) {
    const fs::file_status st = status_of(path);
    if (!fs::exists(st)) {
        require_creatable(key, path);
        return;
    }
    if (fs::is_directory(st)) throw Error(key + ": " + path.string() + " is a folder");
    require_access(key, path, R_OK | W_OK, "open the file for writing");
}

// The epoch database, when it exists: an SQLite file (not a log or a copy gone wrong), and
// its -wal and -shm files as writable as itself (a run as root leaves them root's, and the
// service's user then cannot open the database).
void check_database(const fs::path& path) {
    const fs::file_status st = status_of(path);
    if (!fs::exists(st)) return;
    std::ifstream in(path, std::ios::binary);
    char magic[16] = {};
    in.read(magic, sizeof magic);
    if (in.gcount() > 0 && std::memcmp(magic, "SQLite format 3", 16) != 0) {
        throw Error("paths.database: " + path.string() + " is not an SQLite database");
    }
    for (const char* suffix : {"-wal", "-shm"}) {
        const fs::path side = path.string() + suffix;
        if (fs::exists(status_of(side))) {
            require_access("paths.database", side, R_OK | W_OK,
                           "open the database's " + std::string(suffix + 1) + " file for writing");
        }
    }
}

}  // namespace

std::vector<MissingFolder> check_startup(const Config& c) {
    std::vector<MissingFolder> missing;
    // Apart on disk too: a link or a bind mount can make two written paths one folder.
    if (const auto o = folders_overlap_on_disk(c.paths)) {
        throw Error("paths." + o->key + ": " + o->what);
    }
    // Files leave the ingest folder when they are archived (or removed as copies).
    const int ingest_mode = c.ingest.archive == ArchiveMode::move ? R_OK | W_OK : R_OK;
    check_folder("paths.ingest", c.paths.ingest, ingest_mode, missing);
    check_folder("paths.archive", c.paths.archive, W_OK, missing);
    check_folder("paths.quarantine", c.paths.quarantine, W_OK, missing);
    // SQLite creates its -wal and -shm files beside the database.
    const std::size_t before = missing.size();
    check_folder("paths.database", c.paths.database.parent_path(), W_OK, missing);
    if (missing.size() == before) {
        check_writable_file("paths.database", c.paths.database);
        check_database(c.paths.database);
    }
    if (!c.logging.file.empty()) {
        // Its folder like the others: a missing one is said, and created by `run`.
        const std::size_t folders = missing.size();
        check_folder("logging.file", c.logging.file.parent_path(), W_OK, missing);
        if (missing.size() == folders) check_writable_file("logging.file", c.logging.file);
    }
    return missing;
}

void create_missing_folders(const std::vector<MissingFolder>& missing) {
    for (const auto& m : missing) {
        std::error_code ec;
        fs::create_directories(m.path, ec);
        if (ec) {
            throw Error(m.key + ": " + m.path.string() +
                        ": cannot create the folder: " + ec.message());
        }
        spdlog::warn("{}: {} did not exist; created it", m.key, m.path.string());
    }
}

std::vector<std::string> notify_file_problems(const NotifyConfig& notify) {
    std::vector<std::string> out;
    for (const NotifyChannel& c : notify.channels) {
        const std::pair<const char*, const std::filesystem::path*> files[] = {
            {"password_file", &c.password_file},
            {"token_file", &c.token_file},
            {"ca_file", &c.ca_file}};
        for (const auto& [key, path] : files) {
            if (path->empty() || ::access(path->c_str(), R_OK) == 0) continue;
            out.push_back("notify channel '" + c.name + "': " + key + " " + path->string() + ": " +
                          std::strerror(errno));
        }
    }
    return out;
}

}  // namespace tlsmon
