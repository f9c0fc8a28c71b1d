#pragma once
// The CSV file a one-shot command writes its results to: opened for writing, its lines
// written, closed; a file that cannot be opened, or whose writing or closing fails, is an
// Error naming it and the system's reason.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/error.hpp"

namespace tlsmon {

class ResultFile {
  public:
    explicit ResultFile(std::string path) : path_(std::move(path)) {
        file_ = std::fopen(path_.c_str(), "w");
        if (!file_) throw Error(path_ + ": cannot write: " + std::strerror(errno));
    }
    ~ResultFile() {
        if (file_) std::fclose(file_);
    }
    ResultFile(const ResultFile&) = delete;
    ResultFile& operator=(const ResultFile&) = delete;

    // `text` as it is (a CSV line carries its own line end).
    void write(const std::string& text) { std::fputs(text.c_str(), file_); }

    // Throws when anything written did not reach the file.
    void close() {
        const bool failed = std::ferror(file_) != 0;
        const bool closed = std::fclose(file_) == 0;
        file_ = nullptr;
        if (!closed || failed) throw Error(path_ + ": write failed: " + std::strerror(errno));
    }

  private:
    std::string path_;
    std::FILE* file_ = nullptr;
};

}  // namespace tlsmon
