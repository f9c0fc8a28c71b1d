// The sd_notify protocol as systemd sees it: the test plays systemd's part, with a
// datagram socket in $NOTIFY_SOCKET and $WATCHDOG_USEC set, and reads what the daemon says.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/un.h>

#include <algorithm>
#include <chrono>

#include "tests/support/daemon_harness.hpp"

namespace tlsmon::test {
namespace {

TEST(DaemonSystemd, ReadyWatchdogStatusStopping) {
    Site site("systemd");
    const fs::path socket_path = site.root / "notify.sock";
    const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    ASSERT_GE(fd, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", socket_path.c_str());
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    timeval timeout{0, 200000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

    // 1 s: pings expected every 0.5 s; systemd would kill the unit after 1 s without one.
    constexpr double watchdog_seconds = 1.0;
    ::setenv("NOTIFY_SOCKET", socket_path.c_str(), 1);
    ::setenv("WATCHDOG_USEC", "1000000", 1);
    DaemonProcess daemon(site.config(), site.log());
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");

    using Clock = std::chrono::steady_clock;
    struct Message {
        std::string text;
        Clock::time_point at;
    };
    std::vector<Message> messages;
    // Receives until `done` holds or `seconds` have passed.
    const auto receive_until = [&](double seconds, const auto& done) {
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        char buf[4096];
        while (Clock::now() < end && !done()) {
            const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
            if (n > 0)
                messages.push_back({std::string(buf, static_cast<std::size_t>(n)), Clock::now()});
        }
    };
    // The start time depends on the machine's load; the watchdog's spacing is what is tested,
    // so the pings are counted over a fixed time after READY=1.
    receive_until(30.0, [&] { return !messages.empty(); });
    ASSERT_FALSE(messages.empty()) << read_file(site.log());
    const auto ready_at = messages.front().at;
    receive_until(3.0, [] { return false; });
    daemon.signal(SIGTERM);
    receive_until(5.0, [&] { return messages.back().text == "STOPPING=1"; });
    EXPECT_EQ(daemon.wait(5), 0);
    ::close(fd);

    const auto count = [&](const std::string& prefix) {
        return std::count_if(messages.begin(), messages.end(),
                             [&](const Message& m) { return m.text.rfind(prefix, 0) == 0; });
    };
    EXPECT_EQ(messages.front().text, "READY=1");
    EXPECT_EQ(count("READY=1"), 1);
    EXPECT_GE(count("WATCHDOG=1"), 4) << "pings at half of WATCHDOG_USEC for 3 s after READY=1";
    double longest_gap = 0;
    auto last = ready_at;
    for (const Message& m : messages)
        if (m.text == "WATCHDOG=1") {
            longest_gap = std::max(longest_gap, std::chrono::duration<double>(m.at - last).count());
            last = m.at;
        }
    EXPECT_LT(longest_gap, watchdog_seconds) << "systemd would have killed the unit";
    EXPECT_GE(count("STATUS="), 1);
    EXPECT_EQ(messages.back().text, "STOPPING=1");
}

}  // namespace
}  // namespace tlsmon::test
