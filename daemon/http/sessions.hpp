#pragma once
// Logged-in dashboard users and the brake on guessing passwords, both in memory (a restart
// logs everybody out, which is safe). Thread-safe: the server's threads share one of each.
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/utc_time.hpp"
#include "daemon/http/users.hpp"

namespace tlsmon {

struct Session {
    std::string token;  // the cookie's value: 32 random bytes, hex
    std::string csrf;   // to be sent back in X-CSRF-Token with every POST
    std::string user;
    UserRole role = UserRole::viewer;
    UtcSeconds expires = 0;
};

class Sessions {
  public:
    Session open(const std::string& user, UserRole role, UtcSeconds now, UtcSeconds lifetime);
    // The live session of `token`; expired ones are dropped.
    std::optional<Session> find(const std::string& token, UtcSeconds now);
    void close(const std::string& token);

  private:
    std::mutex mutex_;
    std::map<std::string, Session> sessions_;
};

// Failed logins per client address: after `kMaxFailures` within `kWindow` seconds, every
// login from that address is refused (without checking the password) until the oldest of
// them leaves the window.
class LoginThrottle {
  public:
    static constexpr int kMaxFailures = 5;
    static constexpr UtcSeconds kWindow = 300;

    // 0 when a login may be tried now, else the seconds to wait.
    UtcSeconds wait_before_login(const std::string& address, UtcSeconds now);
    void failed(const std::string& address, UtcSeconds now);
    void succeeded(const std::string& address);

  private:
    std::mutex mutex_;
    std::map<std::string, std::vector<UtcSeconds>> failures_;
};

// `n` random bytes (OpenSSL's RAND_bytes) as hex.
std::string random_token(std::size_t n = 32);
// Whether a token sent by a client is `expected`, in time that does not depend on where
// they differ (OpenSSL's CRYPTO_memcmp), so the answer's timing does not leak the token.
bool same_token(std::string_view sent, std::string_view expected);

}  // namespace tlsmon
