#include "storage/file_access.hpp"

#include <fcntl.h>
#include <unistd.h>

namespace tlsmon {

namespace fs = std::filesystem;

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

}  // namespace tlsmon
