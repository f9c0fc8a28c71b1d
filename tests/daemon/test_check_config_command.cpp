// `tlsmon check-config` and the logging options, through the real binary.
#include <gtest/gtest.h>

#include "daemon_harness.hpp"

namespace tlsmon::test {
namespace {

TEST(CheckConfigCommand, PrintsEffectiveValuesOfTheShippedFile) {
    const auto r = shell(std::string(TLSMON_BINARY) + " check-config " + TLSMON_SOURCE_DIR +
                         "/etc/tlsmon.toml");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("ingest.stable_seconds = 10\n"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ingest.max_growing = 3600\n"), std::string::npos) << r.output;
    const std::string ingest = (fs::path(TLSMON_SOURCE_DIR) / "var/ingest").lexically_normal();
    EXPECT_NE(r.output.find("paths.ingest = \"" + ingest + "\""), std::string::npos) << r.output;
}

TEST(CheckConfigCommand, BadFileExitsOneNamingFileLineAndKey) {
    Site site("checkconfig", "[logging]\nlevel = \"info\"\nmax_files = 0\n");
    const auto r = shell(std::string(TLSMON_BINARY) + " check-config " + site.config().string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("site.toml:16:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("key 'logging.max_files'"), std::string::npos) << r.output;
}

TEST(CheckConfigCommand, LogFileRotatesAndHonoursTheLevel) {
    Site site("logfile",
              "[logging]\nlevel = \"debug\"\nfile = \"log/tlsmon.log\"\nmax_size = 4096\n"
              "max_files = 2\njournald = \"off\"\n");
    for (int i = 0; i < 7; ++i) {
        DaemonProcess once(site.config(), site.log(), true);
        ASSERT_EQ(once.wait(30), 0) << read_file(site.log());
    }
    // Each run logs ~1.9 kB (the effective configuration and more): seven runs rotate
    // twice, and only max_files = 2 old files are kept.
    EXPECT_TRUE(fs::exists(site.root / "log/tlsmon.log"));
    EXPECT_TRUE(fs::exists(site.root / "log/tlsmon.1.log"));
    EXPECT_TRUE(fs::exists(site.root / "log/tlsmon.2.log"));
    EXPECT_FALSE(fs::exists(site.root / "log/tlsmon.3.log"));
    EXPECT_LE(fs::file_size(site.root / "log/tlsmon.1.log"), 4096u);
    EXPECT_NE(read_file(site.root / "log/tlsmon.log").find("logging.level = \"debug\""),
              std::string::npos);
}

}  // namespace
}  // namespace tlsmon::test
