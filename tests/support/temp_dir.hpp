#pragma once
// Helpers shared by every test executable (included as "tests/support/temp_dir.hpp"): a
// fresh scratch folder per test, and whole files written and read as bytes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace tlsmon::test {

// A fresh folder under the system temp folder, removed with everything in it. It is named
// after the running test, or after `label` when one is given (a short name for folders whose
// path ends up in what a test compares, such as the daemon's log), then the process id
// (several test runs may share the machine) and a count that keeps two folders apart.
class TempDir {
  public:
    explicit TempDir(const std::string& label = "") {
        static std::atomic<int> count{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        const std::string name = !label.empty() ? label : info ? info->name() : "test";
        path_ =
            std::filesystem::temp_directory_path() /
            ("tlsmon-" + name + "-" + std::to_string(::getpid()) + "-" + std::to_string(count++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::filesystem::path& name) const {
        return path_ / name;
    }

  private:
    std::filesystem::path path_;
};

// Writes `bytes` as the whole content of `path` (replacing it); returns `path`.
inline std::filesystem::path write_file(const std::filesystem::path& path,
                                        const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

// The whole content of `path` as bytes; "" when it cannot be opened.
inline std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace tlsmon::test
