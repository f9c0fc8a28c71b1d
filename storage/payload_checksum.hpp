#pragma once
// Private to storage/: the checksum stored beside a reference cache payload. SHA-256 (via
// OpenSSL's libcrypto, already a dependency of the daemon) rather than a short hash: the
// payloads are large and long-lived, and the cost (~1 s/GB) is small against recomputing
// them. storage/ computes it itself so no caller can store a payload with a wrong checksum.
#include <string>
#include <string_view>

namespace tlsmon {

// 64 lowercase hex digits.
std::string payload_sha256(std::string_view bytes);

}  // namespace tlsmon
