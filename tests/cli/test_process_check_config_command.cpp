// `tlsmon check-config` and the logging options, through the real binary.
#include <gtest/gtest.h>

#include "tests/support/daemon_harness.hpp"
#include "tests/support/text_file.hpp"

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
              "[logging]\nlevel = \"debug\"\nfile = \"log/tlsmon.log\"\nmax_size = 32768\n"
              "max_files = 2\njournald = \"off\"\n");
    for (int i = 0; i < 7; ++i) {
        DaemonProcess once(site.config(), site.log(), true);
        ASSERT_EQ(once.wait(30), 0) << read_file(site.log());
    }
    // Each run logs ~12 kB (the effective configuration, one line per key, and more): seven
    // runs rotate at least twice, and only max_files = 2 old files are kept.
    EXPECT_TRUE(fs::exists(site.root / "log/tlsmon.log"));
    EXPECT_TRUE(fs::exists(site.root / "log/tlsmon.1.log"));
    EXPECT_TRUE(fs::exists(site.root / "log/tlsmon.2.log"));
    EXPECT_FALSE(fs::exists(site.root / "log/tlsmon.3.log"));
    EXPECT_LE(fs::file_size(site.root / "log/tlsmon.1.log"), 32768u);
    // The last run's effective configuration, wherever the rotation cut it.
    EXPECT_NE((read_file(site.root / "log/tlsmon.1.log") + read_file(site.root / "log/tlsmon.log"))
                  .find("logging.level = \"debug\""),
              std::string::npos);
}

// Two paths that are one folder on disk (a symbolic link): refused by check-config and by
// run before anything is read, moved or deleted.
TEST(CheckConfigCommand, FoldersThatAreOneOnDiskAreRefusedBeforeAnyFileIsTouched) {
    TempDir dir("folderalias");
    fs::create_directories(dir.path() / "ingest");
    fs::create_directory_symlink(dir.path() / "ingest", dir.path() / "done");
    for (int i = 0; i < 3; ++i) {
        write_text(dir.path() / "ingest" / ("scan" + std::to_string(i) + ".xyz"), "1 2 3\n");
    }
    const fs::path config = dir.path() / "site.toml";
    write_text(config,
               "[paths]\ningest = \"ingest/\"\narchive = \"done\"\n"
               "quarantine = \"q\"\ndatabase = \"db/t.sqlite\"\n"
               "[ingest]\nstable_seconds = \"100ms\"\n");
    auto r = shell(std::string(TLSMON_BINARY) + " check-config " + config.string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("paths.archive: " + (dir.path() / "done").string() +
                            " is the folder of paths.ingest"),
              std::string::npos)
        << r.output;
    r = shell(std::string(TLSMON_BINARY) + " run --once --config " + config.string());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("paths.archive"), std::string::npos) << r.output;
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(fs::exists(dir.path() / "ingest" / ("scan" + std::to_string(i) + ".xyz")));
    }
    EXPECT_FALSE(fs::exists(dir.path() / "db"));
}

// `tlsmon check-config` as user `nobody` when the tests run as root, who may read and
// write anything, so that a missing permission is real.
CommandResult check_config_as_nobody(const fs::path& config) {
    const std::string as =
        ::getuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
    return shell(as + TLSMON_BINARY + " check-config " + config.string());
}

TEST(CheckConfigCommand, UnopenableFileGivesTheSystemsReason) {
    Site site("unopenable");
    const fs::path missing = site.root / "sitr.toml";
    auto r = shell(std::string(TLSMON_BINARY) + " check-config " + missing.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.output, "tlsmon check-config: cannot open " + missing.string() +
                            ": No such file or directory\n");
    ::chmod(site.config().c_str(), 0600);  // owned by root or the test's user
    if (::getuid() != 0) ::chmod(site.config().c_str(), 0);
    r = check_config_as_nobody(site.config());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.output, "tlsmon check-config: cannot open " + site.config().string() +
                            ": Permission denied\n");
}

// What `run` rejects at start, `check-config` rejects too, with the same message.
void expect_both_reject(const Site& site, const std::string& message) {
    const auto check =
        shell(std::string(TLSMON_BINARY) + " check-config " + site.config().string());
    EXPECT_EQ(check.status, 1) << check.output;
    EXPECT_NE(check.output.find(message), std::string::npos) << check.output;
    DaemonProcess run(site.config(), site.log(), true);
    EXPECT_EQ(run.wait(30), 1) << read_file(site.log());
    EXPECT_NE(read_file(site.log()).find(message), std::string::npos) << read_file(site.log());
}

TEST(CheckConfigCommand, IngestPathThatIsAFileIsRejected) {
    Site site("ingestfile");
    fs::remove(site.ingest());
    std::ofstream(site.ingest()) << "not a folder\n";
    expect_both_reject(site, "paths.ingest: " + site.ingest().string() + " is not a folder");
}

TEST(CheckConfigCommand, LogFileThatCannotBeOpenedIsRejected) {
    Site site("logfolder", "[logging]\nfile = \"ingest\"\n");
    expect_both_reject(site, "logging.file: " + site.ingest().string() + " is a folder");
}

// A database that passed check-config and then failed `run`: a file that is no SQLite
// database, and a database whose -wal and -shm files were left by a run as root, which
// the service's user cannot open.
TEST(CheckConfigCommand, DatabaseThatRunCannotOpenIsRejected) {
    Site site("notadb");
    fs::create_directories(site.database().parent_path());
    std::ofstream(site.database()) << "notes of the last survey\n";
    expect_both_reject(
        site, "paths.database: " + site.database().string() + " is not an SQLite database");
    fs::remove(site.database());
    ASSERT_EQ(shell("sqlite3 " + site.database().string() + " 'CREATE TABLE t (x)'").status, 0);
    std::ofstream(site.database().string() + "-shm") << std::string(32768, '\0');
    if (::getuid() == 0) {
        ASSERT_EQ(shell("chown -R 65534:65534 " + site.root.string()).status, 0);
        ASSERT_EQ(::chown((site.database().string() + "-shm").c_str(), 0, 0), 0);
    }
    ::chmod((site.database().string() + "-shm").c_str(), 0644);
    const auto r = check_config_as_nobody(site.config());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("paths.database: " + site.database().string() +
                            "-shm: cannot open the database's shm file for writing: "
                            "Permission denied"),
              std::string::npos)
        << r.output;
}

// A log file in a folder that does not exist is said like the other folders (check-config
// warns, `run` creates it and logs there).
TEST(CheckConfigCommand, LogFileInAMissingFolderIsSaidAndCreatedByRun) {
    Site site("logmissing", "[logging]\nfile = \"logs/today/tlsmon.log\"\n");
    const auto check =
        shell(std::string(TLSMON_BINARY) + " check-config " + site.config().string());
    EXPECT_EQ(check.status, 0) << check.output;
    EXPECT_NE(check.output.find("warning: logging.file: " + (site.root / "logs/today").string() +
                                " does not exist; tlsmon run will create it"),
              std::string::npos)
        << check.output;
    EXPECT_FALSE(fs::exists(site.root / "logs"));
    DaemonProcess run(site.config(), site.log(), true);
    EXPECT_EQ(run.wait(30), 0) << read_file(site.log());
    EXPECT_NE(read_file(site.root / "logs/today/tlsmon.log").find("tlsmon started"),
              std::string::npos);
}

TEST(CheckConfigCommand, DatabaseFolderNotWritableIsRejected) {
    Site site("dbfolder");
    fs::create_directories(site.database().parent_path());
    if (::getuid() == 0) {
        ASSERT_EQ(shell("chown -R 65534:65534 " + site.root.string()).status, 0);
        ASSERT_EQ(::chown(site.database().parent_path().c_str(), 0, 0), 0);
    }
    ::chmod(site.database().parent_path().c_str(), 0555);
    const auto r = check_config_as_nobody(site.config());
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("paths.database: " + site.database().parent_path().string() +
                            ": cannot write files in the folder: Permission denied"),
              std::string::npos)
        << r.output;
    ::chmod(site.database().parent_path().c_str(), 0755);
}

TEST(CheckConfigCommand, MissingIngestFolderIsNamedAndCreatedOnlyByRun) {
    Site site("noingest");
    fs::remove(site.ingest());
    const auto check =
        shell(std::string(TLSMON_BINARY) + " check-config " + site.config().string());
    EXPECT_EQ(check.status, 0) << check.output;
    EXPECT_NE(check.output.find("warning: paths.ingest: " + site.ingest().string() +
                                " does not exist; tlsmon run will create it"),
              std::string::npos)
        << check.output;
    EXPECT_FALSE(fs::exists(site.ingest()));
    EXPECT_FALSE(fs::exists(site.root / "archive"));

    DaemonProcess run(site.config(), site.log(), true);
    ASSERT_EQ(run.wait(30), 0) << read_file(site.log());
    EXPECT_TRUE(fs::is_directory(site.ingest()));
    EXPECT_NE(
        read_file(site.log())
            .find("warning paths.ingest: " + site.ingest().string() + " did not exist; created it"),
        std::string::npos)
        << read_file(site.log());
}

}  // namespace
}  // namespace tlsmon::test
