#include "daemon/systemd_notify.hpp"

#include <systemd/sd-daemon.h>

namespace tlsmon {

SystemdNotify::SystemdNotify() : last_ping_(std::chrono::steady_clock::now()) {
    std::uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
        watchdog_period_ = std::chrono::microseconds(usec / 2);
    }
}

void SystemdNotify::ready() {
    sd_notify(0, "READY=1");
}

void SystemdNotify::stopping() {
    sd_notify(0, "STOPPING=1");
}

void SystemdNotify::status(const std::string& text) {
    sd_notify(0, ("STATUS=" + text).c_str());
}

void SystemdNotify::watchdog() {
    if (!watchdog_period_) return;
    sd_notify(0, "WATCHDOG=1");
    last_ping_ = std::chrono::steady_clock::now();
}

void SystemdNotify::watchdog_if_due() {
    if (!watchdog_period_) return;
    if (std::chrono::steady_clock::now() - last_ping_ >= *watchdog_period_) watchdog();
}

std::optional<std::chrono::steady_clock::duration> SystemdNotify::until_watchdog() const {
    if (!watchdog_period_) return std::nullopt;
    const auto due = last_ping_ + *watchdog_period_;
    const auto now = std::chrono::steady_clock::now();
    return due > now ? due - now : std::chrono::steady_clock::duration::zero();
}

}  // namespace tlsmon
