// The sd_notify protocol as systemd sees it: the test plays systemd's part, with a
// datagram socket in $NOTIFY_SOCKET and $WATCHDOG_USEC set, and reads what the daemon says.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/un.h>

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

    ::setenv("NOTIFY_SOCKET", socket_path.c_str(), 1);
    ::setenv("WATCHDOG_USEC", "400000", 1);  // 0.4 s: pings expected every 0.2 s
    DaemonProcess daemon(site.config(), site.log());
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");

    std::vector<std::string> messages;
    const auto receive_for = [&](double seconds) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        char buf[4096];
        while (std::chrono::steady_clock::now() < end) {
            const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
            if (n > 0) messages.emplace_back(buf, static_cast<std::size_t>(n));
        }
    };
    receive_for(2.0);
    daemon.signal(SIGTERM);
    receive_for(0.5);
    EXPECT_EQ(daemon.wait(5), 0);
    ::close(fd);

    const auto count = [&](const std::string& prefix) {
        return std::count_if(messages.begin(), messages.end(),
                             [&](const std::string& m) { return m.rfind(prefix, 0) == 0; });
    };
    ASSERT_FALSE(messages.empty()) << read_file(site.log());
    EXPECT_EQ(messages.front(), "READY=1");
    EXPECT_EQ(count("READY=1"), 1);
    EXPECT_GE(count("WATCHDOG=1"), 5) << "pings at half of WATCHDOG_USEC for ~1.8 s";
    EXPECT_GE(count("STATUS="), 1);
    EXPECT_EQ(messages.back(), "STOPPING=1");
}

}  // namespace
}  // namespace tlsmon::test
