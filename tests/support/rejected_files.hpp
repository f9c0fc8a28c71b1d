#pragma once
// A fixture for reader tests on broken text files: writes them into a temporary folder and
// expects read_scans (which picks the reader by extension) to reject each with a
// FormatError "<file>:<line>: ..." that contains a given phrase.
#include <gtest/gtest.h>

#include <string>

#include "formats/format_error.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test {

class RejectedFiles : public ::testing::Test {
  protected:
    std::filesystem::path write(const std::string& name, const std::string& content) const {
        return write_file(dir_ / name, content);
    }

    static void expect_rejected(const std::filesystem::path& p, int line, const std::string& what) {
        try {
            read_scans(p);
            ADD_FAILURE() << p << " was accepted";
        } catch (const FormatError& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.rfind(p.string() + ":" + std::to_string(line) + ": ", 0), 0u) << msg;
            EXPECT_NE(msg.find(what), std::string::npos) << msg;
        }
    }

    TempDir dir_;
};

}  // namespace tlsmon::test
