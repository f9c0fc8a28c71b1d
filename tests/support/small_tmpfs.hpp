#pragma once
// A small tmpfs mounted for a disk-full test (mounting needs root, as in CI), and filling
// a file system up.
#include <sys/mount.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace tlsmon::test {

// Mounts a tmpfs of `size` (mount's size= option, e.g. "1m") at `at`, creating the folder;
// unmounts it (lazily, so that an open file cannot keep it) when destroyed.
class SmallTmpfs {
  public:
    SmallTmpfs(const std::filesystem::path& at, const std::string& size) : at_(at) {
        std::filesystem::create_directories(at_);
        mounted_ = ::mount("tlsmon-test", at_.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0;
        if (!mounted_) error_ = std::strerror(errno);
    }
    ~SmallTmpfs() {
        if (mounted_) ::umount2(at_.c_str(), MNT_DETACH);
    }
    SmallTmpfs(const SmallTmpfs&) = delete;
    SmallTmpfs& operator=(const SmallTmpfs&) = delete;

    bool mounted() const { return mounted_; }
    // Why mounting failed ("" when mounted).
    const std::string& error() const { return error_; }

  private:
    std::filesystem::path at_;
    bool mounted_ = false;
    std::string error_;
};

// Fills the file system holding `file` by writing `file` until a write fails.
inline void fill_file_system(const std::filesystem::path& file) {
    std::ofstream out(file, std::ios::binary);
    const std::string block(4096, 'x');
    while (out.write(block.data(), block.size())) out.flush();
}

}  // namespace tlsmon::test
