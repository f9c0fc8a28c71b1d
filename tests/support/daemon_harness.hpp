#pragma once
// Running the real `tlsmon` binary (TLSMON_BINARY) in tests: a scratch site folder with a
// configuration, the daemon as a child process (optionally as another user), shell
// commands with their output, and waiting for a condition with a deadline.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test {

namespace fs = std::filesystem;

// Output (stdout + stderr) and exit status of a shell command.
struct CommandResult {
    int status = -1;
    std::string output;
};

inline CommandResult shell(const std::string& command) {
    CommandResult r;
    FILE* p = ::popen((command + " 2>&1").c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

// Polls `done` until it holds or `seconds` pass. A database still being created by the
// daemon (absent, or not yet migrated) counts as "not yet".
inline bool wait_until(const std::function<bool()>& done, double seconds) {
    const auto check = [&] {
        try {
            return done();
        } catch (const StorageError&) {
            return false;
        }
    };
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (check()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return check();
}

// A scratch site: ingest/, archive/, quarantine/, db/, and site.toml with short timings, in
// a fresh folder (labelled `name`) removed at the end. Its [meteo] section comes last; by
// default scans do not wait for a meteo sidecar (wait_seconds = 0).
class Site {
  public:
    explicit Site(const std::string& name, const std::string& extra_toml = "",
                  const std::string& ingest_toml = "",
                  const std::string& meteo_toml = "wait_seconds = 0\n")
        : dir_(name), root(dir_.path()) {
        fs::create_directories(root / "ingest");
        std::ofstream(root / "site.toml")
            << "[station]\nname = \"small\"\n"
            << "[paths]\ningest = \"ingest\"\narchive = \"archive\"\n"
            << "quarantine = \"quarantine\"\ndatabase = \"db/tlsmon.sqlite\"\n"
            << "[ingest]\nstable_seconds = \"300ms\"\nrescan_interval = 1\n"
            << "retry_initial = \"500ms\"\nretry_max = 2\n"
            << ingest_toml << "\n"
            << extra_toml << "\n[meteo]\n"
            << meteo_toml;
    }
    fs::path ingest() const { return root / "ingest"; }
    fs::path config() const { return root / "site.toml"; }
    fs::path database() const { return root / "db/tlsmon.sqlite"; }
    fs::path log() const { return root / "daemon.log"; }

    EpochDatabase open_db() const {
        return EpochDatabase::open(database(), EpochDatabase::Mode::read_only);
    }

  private:
    TempDir dir_;

  public:
    fs::path root;
};

// `tlsmon run --config FILE` as a child process; stdout and stderr go to `log`.
class DaemonProcess {
  public:
    DaemonProcess(const fs::path& config, const fs::path& log, bool once = false,
                  std::optional<uid_t> as_user = std::nullopt) {
        pid_ = ::fork();
        if (pid_ == 0) {
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            if (as_user) {
                if (::setgid(*as_user) != 0 || ::setuid(*as_user) != 0) ::_exit(126);
            }
            if (once) {
                ::execl(TLSMON_BINARY, TLSMON_BINARY, "run", "--config", config.c_str(), "--once",
                        nullptr);
            } else {
                ::execl(TLSMON_BINARY, TLSMON_BINARY, "run", "--config", config.c_str(), nullptr);
            }
            ::_exit(127);
        }
    }
    ~DaemonProcess() {
        if (running()) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
    }
    pid_t pid() const { return pid_; }
    bool running() {
        if (exited_) return false;
        int st = 0;
        if (::waitpid(pid_, &st, WNOHANG) == pid_) {
            exited_ = true;
            status_ = st;
            return false;
        }
        return true;
    }
    void signal(int sig) { ::kill(pid_, sig); }
    // Waits for the exit; returns the exit code, or -1 on timeout / -2 if killed by a signal.
    int wait(double seconds) {
        if (!wait_until([this] { return !running(); }, seconds)) return -1;
        return WIFEXITED(status_) ? WEXITSTATUS(status_) : -2;
    }

  private:
    pid_t pid_ = -1;
    bool exited_ = false;
    int status_ = 0;
};

// A server or client the test needs beside the daemon (a broker, a receiver): `command` run
// by /bin/sh in a process group of its own, its output to `log`; the group is ended with the
// object.
class ChildProcess {
  public:
    ChildProcess(const std::string& command, const fs::path& log) {
        pid_ = ::fork();
        if (pid_ == 0) {
            ::setpgid(0, 0);
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            ::execl("/bin/sh", "sh", "-c", command.c_str(), nullptr);
            ::_exit(127);
        }
        ::setpgid(pid_, pid_);
    }
    ~ChildProcess() {
        ::kill(-pid_, SIGTERM);
        if (!wait_until([this] { return ::waitpid(pid_, nullptr, WNOHANG) == pid_; }, 5)) {
            ::kill(-pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
    }
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

  private:
    pid_t pid_ = -1;
};

}  // namespace tlsmon::test
