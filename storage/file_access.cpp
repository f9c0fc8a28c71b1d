#include "storage/file_access.hpp"

#include <fcntl.h>
#include <pwd.h>
#include <unistd.h>

#include <vector>

namespace tlsmon {

namespace fs = std::filesystem;

std::string effective_user() {
    const uid_t uid = ::geteuid();
    std::vector<char> buf(16384);
    passwd pw{};
    passwd* found = nullptr;
    const std::string id = "uid " + std::to_string(uid);
    if (::getpwuid_r(uid, &pw, buf.data(), buf.size(), &found) == 0 && found) {
        return "user " + std::string(found->pw_name) + " (" + id + ")";
    }
    return "user " + id;
}

namespace {

// access(2) with the effective ids, as the kernel checks them on open.
bool may(const fs::path& p, int mode) {
    return ::faccessat(AT_FDCWD, p.c_str(), mode, AT_EACCESS) == 0;
}

fs::path folder_of(const fs::path& database) {
    return database.has_parent_path() ? database.parent_path() : fs::current_path();
}

}  // namespace

bool folder_writable(const fs::path& database) {
    return may(folder_of(database), W_OK | X_OK);
}

std::optional<std::string> missing_write_permission(const fs::path& database) {
    const fs::path folder = folder_of(database);
    const std::string name = database.filename().string();
    const std::string by = " by " + effective_user();
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) {
        return "cannot create the database " + name + ": folder " + folder.string() +
               " does not exist";
    }
    if (!may(folder, X_OK)) {
        return "cannot open the database " + name + ": folder " + folder.string() +
               " cannot be entered (no search permission)" + by;
    }
    const bool file_exists = fs::exists(database, ec);
    if (!file_exists && !may(folder, W_OK)) {
        return "cannot create the database " + name + ": folder " + folder.string() +
               " is not writable" + by;
    }
    if (file_exists && !may(database, R_OK | W_OK)) {
        return "cannot write the database " + database.string() + ": the file is not " +
               (may(database, R_OK) ? "writable" : "readable and writable") + by;
    }
    // WAL mode keeps two files beside the database, created by whoever opens it first.
    for (const char* suffix : {"-wal", "-shm"}) {
        const fs::path side = database.string() + suffix;
        if (fs::exists(side, ec)) {
            if (!may(side, R_OK | W_OK)) {
                return "cannot write the database " + name + ": " + side.string() +
                       " is not writable" + by;
            }
        } else if (!may(folder, W_OK)) {
            return "cannot write the database " + name + ": folder " + folder.string() +
                   " is not writable" + by + " (SQLite creates " + side.filename().string() +
                   " there)";
        }
    }
    return std::nullopt;
}

}  // namespace tlsmon
