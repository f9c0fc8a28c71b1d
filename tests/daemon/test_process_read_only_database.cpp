// Defect 9: `tlsmon status|query` read a database in a folder the user cannot write (the
// daemon's folder, read by an operator), as another user than the one that wrote it, in
// every state the daemon can leave the files in: closed cleanly (no -wal/-shm), running (its
// -wal and -shm beside the file), killed (both left behind).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "storage/epoch_database.hpp"
#include "tests/support/daemon_harness.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

// The binary as `nobody` when the test runs as root (root may write any folder, so the
// defect would not show), else as the test's own user, who cannot write a 0555 folder either.
test::CommandResult run_as_reader(const std::string& args) {
    const std::string as =
        ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
    return test::shell(as + TLSMON_BINARY + " " + args);  // stdout and stderr
}

std::string sha(int n) {
    std::string s(64, 'b');
    s.back() = static_cast<char>('0' + n);
    return s;
}

class ReadOnlyFolder : public ::testing::Test {
  protected:
    void SetUp() override {
        folder_ = dir_ / "db";
        fs::create_directories(folder_);
        path_ = folder_ / "tlsmon.sqlite";
        auto db = EpochDatabase::open(path_, EpochDatabase::Mode::read_write);
        add_epoch(db, 1);
        add_epoch(db, 2);
    }
    void TearDown() override { ::chmod(folder_.c_str(), 0755); }  // so TempDir can remove it

    static void add_epoch(EpochDatabase& db, int n) {
        db.epochs().insert({sha(n), 1772366400 + n, "/ingest/s.ptx", 10, std::nullopt});
    }
    void lock_folder() { ASSERT_EQ(::chmod(folder_.c_str(), 0555), 0); }
    void unlock_folder() { ASSERT_EQ(::chmod(folder_.c_str(), 0755), 0); }
    bool exists(const std::string& suffix) const { return fs::exists(path_.string() + suffix); }

    // `tlsmon status` as the reader: succeeds and counts `pending` epochs.
    void expect_status(int pending) {
        const auto r = run_as_reader("status --format json --db " + path_.string());
        ASSERT_EQ(r.status, 0) << r.output;
        const auto j = nlohmann::json::parse(r.output);
        EXPECT_EQ(j["epochs_pending"], pending) << r.output;
        EXPECT_EQ(j["database"], path_.string());
        const auto q = run_as_reader("query epochs --format csv --db " + path_.string());
        ASSERT_EQ(q.status, 0) << q.output;
        EXPECT_NE(q.output.find(sha(pending)), std::string::npos) << q.output;
    }

    test::TempDir dir_;
    fs::path folder_;
    fs::path path_;
};

TEST_F(ReadOnlyFolder, StatusAfterACleanClose) {
    ASSERT_FALSE(exists("-wal"));  // the last connection removed them
    ASSERT_FALSE(exists("-shm"));
    lock_folder();
    expect_status(2);
    EXPECT_FALSE(exists("-wal"));
    EXPECT_FALSE(exists("-shm"));
}

TEST_F(ReadOnlyFolder, StatusWhileTheDaemonWrites) {
    auto writer = EpochDatabase::open(path_, EpochDatabase::Mode::read_write);
    add_epoch(writer, 3);  // committed into the -wal only
    ASSERT_TRUE(exists("-wal"));
    ASSERT_TRUE(exists("-shm"));
    lock_folder();
    expect_status(3);
    unlock_folder();
    add_epoch(writer, 4);  // a later commit is seen by the next reader
    lock_folder();
    expect_status(4);
}

TEST_F(ReadOnlyFolder, StatusAfterTheDaemonWasKilled) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {  // a writer that dies without closing: its -wal and -shm stay
        auto db = EpochDatabase::open(path_, EpochDatabase::Mode::read_write);
        add_epoch(db, 3);
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(exists("-wal"));
    lock_folder();
    expect_status(3);  // the epoch committed into the left-over -wal counts
}

}  // namespace
}  // namespace tlsmon
