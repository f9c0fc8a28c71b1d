#pragma once
// The sd_notify(3) protocol of a Type=notify unit: READY=1 once serving, WATCHDOG=1 at half
// the unit's WatchdogSec (sd_watchdog_enabled(3)), STATUS= a one-line summary, STOPPING=1.
// Outside systemd ($NOTIFY_SOCKET unset) every call does nothing.
#include <chrono>
#include <optional>
#include <string>

namespace tlsmon {

class SystemdNotify {
  public:
    SystemdNotify();
    void ready();
    void stopping();
    void status(const std::string& text);
    // Sends WATCHDOG=1 now (before a long step, so that it gets the whole interval).
    void watchdog();
    // Sends WATCHDOG=1 when half the watchdog interval has passed since the last one.
    void watchdog_if_due();
    // Time until the next watchdog ping is due (nullopt: no watchdog).
    std::optional<std::chrono::steady_clock::duration> until_watchdog() const;

  private:
    std::optional<std::chrono::steady_clock::duration> watchdog_period_;
    std::chrono::steady_clock::time_point last_ping_;
};

}  // namespace tlsmon
