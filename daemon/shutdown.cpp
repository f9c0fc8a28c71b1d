#include "daemon/shutdown.hpp"

#include <poll.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/eventfd.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

#include "core/error.hpp"

namespace tlsmon {

Shutdown::Shutdown() : event_fd_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
    if (event_fd_ < 0) throw Error(std::string("eventfd: ") + std::strerror(errno));
}

Shutdown::~Shutdown() {
    ::close(event_fd_);
}

void Shutdown::wake() {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(event_fd_, &one, sizeof one);
    std::lock_guard lock(mutex_);
    cv_.notify_all();
}

void Shutdown::request_stop() {
    stop_ = true;
    wake();
}

void Shutdown::request_reload() {
    reload_ = true;
    wake();
}

bool Shutdown::take_reload() {
    return reload_.exchange(false);
}

void Shutdown::clear_wakeup() {
    std::uint64_t value = 0;
    [[maybe_unused]] const ssize_t n = ::read(event_fd_, &value, sizeof value);
}

bool Shutdown::wait_for(std::chrono::duration<double> d) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, d, [this] { return stop_.load(); });
}

namespace {

sigset_t daemon_signals() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGHUP);
    return set;
}

}  // namespace

void SignalThread::block_signals() {
    const sigset_t set = daemon_signals();
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

SignalThread::SignalThread(Shutdown& shutdown) : shutdown_(shutdown) {
    const sigset_t set = daemon_signals();
    signal_fd_ = ::signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC);
    if (signal_fd_ < 0) throw Error(std::string("signalfd: ") + std::strerror(errno));
    quit_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (quit_fd_ < 0) throw Error(std::string("eventfd: ") + std::strerror(errno));
    thread_ = std::thread([this] { run(); });
}

SignalThread::~SignalThread() {
    shutdown_.request_stop();
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(quit_fd_, &one, sizeof one);
    if (thread_.joinable()) thread_.join();
    ::close(signal_fd_);
    ::close(quit_fd_);
}

void SignalThread::run() {
    for (;;) {
        pollfd fds[2] = {{signal_fd_, POLLIN, 0}, {quit_fd_, POLLIN, 0}};
        if (::poll(fds, 2, -1) < 0 && errno != EINTR) break;
        if (fds[1].revents & POLLIN) break;
        signalfd_siginfo info;
        while (::read(signal_fd_, &info, sizeof info) == sizeof info) {
            if (info.ssi_signo == SIGHUP) {
                spdlog::info("SIGHUP: reloading the configuration");
                shutdown_.request_reload();
            } else {
                spdlog::info("{}: stopping", strsignal(static_cast<int>(info.ssi_signo)));
                shutdown_.request_stop();
            }
        }
    }
}

}  // namespace tlsmon
