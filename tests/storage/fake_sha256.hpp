#pragma once
// A well-formed sha256 for storage tests.
#include <string>

namespace tlsmon::test {

// A well-formed sha256 that differs per `n`.
inline std::string fake_sha256(int n) {
    std::string s(64, '0');
    const std::string digits = std::to_string(n);
    s.replace(64 - digits.size(), digits.size(), digits);
    return s;
}

}  // namespace tlsmon::test
