#pragma once
// A fresh directory under the system temp folder, removed with everything in it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace tlsmon::test {

class TempDir {
  public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = std::filesystem::temp_directory_path() /
                ("tlsmon-" + std::string(info ? info->name() : "test") + "-" +
                 std::to_string(::getpid()));
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
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  private:
    std::filesystem::path path_;
};

// A well-formed sha256 that differs per `n`.
inline std::string fake_sha256(int n) {
    std::string s(64, '0');
    const std::string digits = std::to_string(n);
    s.replace(64 - digits.size(), digits.size(), digits);
    return s;
}

}  // namespace tlsmon::test
