#pragma once
// The one error type of storage/: an SQLite failure with the SQL context in the message and
// SQLite's result codes kept, so a caller can tell a full disk or a lock from a bad epoch.
#include <string>

#include "core/error.hpp"

namespace tlsmon {

class StorageError : public Error {
  public:
    StorageError(const std::string& what, int sqlite_code = 0, int extended_code = 0);
    int sqlite_code() const noexcept { return sqlite_code_; }
    int extended_code() const noexcept { return extended_code_; }
    // SQLITE_FULL or a disk I/O error (SQLITE_IOERR*): the disk, not the epoch, is at fault.
    // The daemon keeps the epoch (Epochs::release) and retries later instead of failing it.
    bool disk_full() const noexcept;
    // SQLITE_BUSY / SQLITE_LOCKED after the busy timeout: another connection held the lock.
    bool busy() const noexcept;

  private:
    int sqlite_code_;
    int extended_code_;
};

}  // namespace tlsmon
