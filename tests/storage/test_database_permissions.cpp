// Defect 11: a writer that may not write the database's folder or file gets an error naming
// the folder or file and the permission missing, not only SQLite's "unable to open database
// file".
#include <grp.h>
#include <gtest/gtest.h>
#include <pwd.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

// Root may write anything, so as root the open runs in a child as `nobody`; otherwise as the
// test's own user, whom a 0555 folder stops as well.
const uid_t kUser = ::geteuid() == 0 ? 65534 : ::geteuid();

std::string user_words() {
    const passwd* pw = ::getpwuid(kUser);
    const std::string id = "uid " + std::to_string(kUser);
    return pw ? "user " + std::string(pw->pw_name) + " (" + id + ")" : "user " + id;
}

// The StorageError of a read_write open of `path` as kUser ("" if it opened).
std::string open_error(const fs::path& path) {
    int fds[2];
    if (::pipe(fds) != 0) return "pipe failed";
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(fds[0]);
        if (::geteuid() == 0 &&
            (::setgroups(0, nullptr) != 0 || ::setresgid(65534, 65534, 65534) != 0 ||
             ::setresuid(65534, 65534, 65534) != 0)) {
            ::_exit(2);
        }
        std::string what;
        try {
            EpochDatabase::open(path, EpochDatabase::Mode::read_write);
        } catch (const StorageError& e) {
            what = e.what();
        }
        const bool written =
            ::write(fds[1], what.data(), what.size()) == static_cast<ssize_t>(what.size());
        ::_exit(written ? 0 : 3);
    }
    ::close(fds[1]);
    std::string out;
    char buf[4096];
    for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) out.append(buf, n);
    ::close(fds[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
    return out;
}

class DatabasePermissions : public ::testing::Test {
  protected:
    void SetUp() override {
        folder_ = dir_ / "db";
        fs::create_directories(folder_);
        path_ = folder_ / "tlsmon.sqlite";
    }
    void TearDown() override { ::chmod(folder_.c_str(), 0755); }

    test::TempDir dir_;
    fs::path folder_;
    fs::path path_;
};

TEST_F(DatabasePermissions, NewDatabaseInAReadOnlyFolderNamesTheFolder) {
    ASSERT_EQ(::chmod(folder_.c_str(), 0555), 0);
    const std::string what = open_error(path_);
    EXPECT_EQ(what.rfind("cannot create the database tlsmon.sqlite: folder " + folder_.string() +
                             " is not writable by " + user_words(),
                         0),
              0u)
        << what;
    EXPECT_FALSE(fs::exists(path_));
}

TEST_F(DatabasePermissions, ExistingDatabaseInAReadOnlyFolderNamesTheFolderAndTheWal) {
    EpochDatabase::open(path_, EpochDatabase::Mode::read_write);  // closed: no -wal, no -shm
    ASSERT_EQ(::chmod(path_.c_str(), 0666), 0);                   // the file itself is writable
    ASSERT_EQ(::chmod(folder_.c_str(), 0555), 0);
    const std::string what = open_error(path_);
    EXPECT_EQ(what.rfind("cannot write the database tlsmon.sqlite: folder " + folder_.string() +
                             " is not writable by " + user_words() +
                             " (SQLite creates tlsmon.sqlite-wal there)",
                         0),
              0u)
        << what;
}

TEST_F(DatabasePermissions, ReadOnlyFileNamesTheFile) {
    EpochDatabase::open(path_, EpochDatabase::Mode::read_write);
    ASSERT_EQ(::chmod(path_.c_str(), 0444), 0);
    ASSERT_EQ(::chmod(folder_.c_str(), 0777), 0);  // the folder is not the problem
    const std::string what = open_error(path_);
    EXPECT_EQ(what.rfind("cannot write the database " + path_.string() +
                             ": the file is not writable by " + user_words(),
                         0),
              0u)
        << what;
}

TEST_F(DatabasePermissions, WritableFolderOpens) {
    ASSERT_EQ(::chmod(folder_.c_str(), 0777), 0);
    EXPECT_EQ(open_error(path_), "");
    EXPECT_TRUE(fs::exists(path_));
}

}  // namespace
}  // namespace tlsmon
