#include "demo/daemon_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "core/error.hpp"

namespace tlsmon {

DaemonChild::DaemonChild(const std::filesystem::path& binary, const std::filesystem::path& config,
                         const std::filesystem::path& log) {
    pid_ = ::fork();
    if (pid_ < 0) throw Error("cannot start the daemon: fork failed");
    if (pid_ == 0) {
        ::setpgid(0, 0);
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
        if (fd >= 0) {
            ::dup2(fd, 1);
            ::dup2(fd, 2);
        }
        ::execl(binary.c_str(), binary.c_str(), "run", "--config", config.c_str(), nullptr);
        ::_exit(127);
    }
    ::setpgid(pid_, pid_);  // also from here, so it holds before either side goes on
}

DaemonChild::~DaemonChild() {
    if (running()) stop();
}

bool DaemonChild::running() {
    if (exited_ || pid_ <= 0) return false;
    int st = 0;
    if (::waitpid(pid_, &st, WNOHANG) == pid_) {
        exited_ = true;
        status_ = st;
        return false;
    }
    return true;
}

int DaemonChild::exit_code() const {
    return exited_ && WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
}

int DaemonChild::stop(double seconds) {
    if (running()) {
        ::kill(pid_, SIGTERM);
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (running() && std::chrono::steady_clock::now() < end) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        if (running()) {
            ::kill(pid_, SIGKILL);
            int st = 0;
            ::waitpid(pid_, &st, 0);
            exited_ = true;
            status_ = st;
            return -1;
        }
    }
    return exit_code();
}

std::filesystem::path own_executable() {
    return std::filesystem::read_symlink("/proc/self/exe");
}

}  // namespace tlsmon
