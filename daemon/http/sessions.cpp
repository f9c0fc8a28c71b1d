#include "daemon/http/sessions.hpp"

#include <openssl/crypto.h>
#include <openssl/rand.h>

#include <algorithm>

#include "core/error.hpp"
#include "core/hex.hpp"

namespace tlsmon {

std::string random_token(std::size_t n) {
    std::vector<unsigned char> bytes(n);
    if (RAND_bytes(bytes.data(), static_cast<int>(n)) != 1)
        throw Error("no random bytes for a session token (OpenSSL)");
    return to_hex(bytes);
}

bool same_token(std::string_view sent, std::string_view expected) {
    return sent.size() == expected.size() &&
           CRYPTO_memcmp(sent.data(), expected.data(), expected.size()) == 0;
}

Session Sessions::open(const std::string& user, UserRole role, UtcSeconds now,
                       UtcSeconds lifetime) {
    Session s{random_token(), random_token(), user, role, now + lifetime};
    std::lock_guard lock(mutex_);
    for (auto it = sessions_.begin(); it != sessions_.end();) {  // the expired, while here
        it = it->second.expires <= now ? sessions_.erase(it) : std::next(it);
    }
    sessions_[s.token] = s;
    return s;
}

std::optional<Session> Sessions::find(const std::string& token, UtcSeconds now) {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(token);
    if (it == sessions_.end()) return std::nullopt;
    if (it->second.expires <= now) {
        sessions_.erase(it);
        return std::nullopt;
    }
    return it->second;
}

void Sessions::close(const std::string& token) {
    std::lock_guard lock(mutex_);
    sessions_.erase(token);
}

UtcSeconds LoginThrottle::wait_before_login(const std::string& address, UtcSeconds now) {
    std::lock_guard lock(mutex_);
    const auto it = failures_.find(address);
    if (it == failures_.end()) return 0;
    auto& f = it->second;
    f.erase(std::remove_if(f.begin(), f.end(), [&](UtcSeconds t) { return t <= now - kWindow; }),
            f.end());
    if (f.empty()) {
        failures_.erase(it);
        return 0;
    }
    if (static_cast<int>(f.size()) < kMaxFailures) return 0;
    return std::max<UtcSeconds>(1, f.front() + kWindow - now);
}

void LoginThrottle::failed(const std::string& address, UtcSeconds now) {
    std::lock_guard lock(mutex_);
    failures_[address].push_back(now);
}

void LoginThrottle::succeeded(const std::string& address) {
    std::lock_guard lock(mutex_);
    failures_.erase(address);
}

}  // namespace tlsmon
