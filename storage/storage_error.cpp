#include "storage/storage_error.hpp"

#include <sqlite3.h>

namespace tlsmon {

StorageError::StorageError(const std::string& what, int sqlite_code, int extended_code)
    : Error(what), sqlite_code_(sqlite_code), extended_code_(extended_code) {}

namespace {

// Primary codes are the low byte of extended codes (sqlite.org/rescode.html).
bool has_primary(int sqlite_code, int extended_code, int a, int b) {
    for (int code : {sqlite_code, extended_code}) {
        if (code <= 0) continue;
        const int primary = code & 0xff;
        if (primary == a || primary == b) return true;
    }
    return false;
}

}  // namespace

bool StorageError::disk_full() const noexcept {
    return has_primary(sqlite_code_, extended_code_, SQLITE_FULL, SQLITE_IOERR);
}

bool StorageError::busy() const noexcept {
    return has_primary(sqlite_code_, extended_code_, SQLITE_BUSY, SQLITE_LOCKED);
}

}  // namespace tlsmon
