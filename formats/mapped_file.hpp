#pragma once
// A read-only memory map of a whole file: readers parse straight from the page cache
// without copying (the ASCII readers reach their speed target this way).
#include <cstddef>
#include <filesystem>
#include <string_view>

namespace tlsmon {

class MappedFile {
  public:
    explicit MappedFile(const std::filesystem::path& path);  // throws FormatError
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    const char* data() const { return data_; }
    std::size_t size() const { return size_; }
    std::string_view text() const { return {data_, size_}; }
    const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
    const char* data_ = nullptr;
    std::size_t size_ = 0;
};

}  // namespace tlsmon
