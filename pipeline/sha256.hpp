#pragma once
// SHA-256 (FIPS 180-4) of a whole file: the identity of a scan in the epoch database.
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/error.hpp"

namespace tlsmon {

// A file that cannot be opened or read (permission, I/O error, vanished).
class FileAccessError : public Error {
  public:
    FileAccessError(const std::string& what, int error_number)
        : Error(what), error_number_(error_number) {}
    int error_number() const noexcept { return error_number_; }

  private:
    int error_number_;
};

// 64 lower-case hex digits. Throws FileAccessError; a symbolic link is never followed
// (error number ELOOP), nor is anything but a regular file read (EINVAL).
std::string sha256_file(const std::filesystem::path& path);
// The same for bytes in memory.
std::string sha256_text(const std::string& bytes);

// Size and modification time (ns) of a file: unchanged stamps say it was not rewritten.
struct FileStamp {
    std::int64_t size = -1;
    std::int64_t mtime_ns = -1;
    bool operator==(const FileStamp&) const = default;
};
// The stamp of the directory entry itself (a symbolic link is not followed); {-1, -1} when
// it cannot be read.
FileStamp file_stamp(const std::filesystem::path& path);

// A whole file in memory with the SHA-256 of exactly those bytes, and the file's stamp when
// it was opened.
struct HashedBytes {
    std::string bytes;
    std::string sha256;
    FileStamp stamp;
};
// Reads the file once, straight into its final buffer, and hashes each chunk while it is
// still in cache: one pass over the data, so the bytes the daemon parses are the bytes whose
// hash it compares with the epoch's. Throws FileAccessError.
HashedBytes read_file_hashed(const std::filesystem::path& path);

}  // namespace tlsmon
