#include "storage/payload_checksum.hpp"

#include <openssl/evp.h>

#include "core/hex.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

std::string payload_sha256(std::string_view bytes) {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    if (EVP_Digest(bytes.data(), bytes.size(), md, &n, EVP_sha256(), nullptr) != 1) {
        throw StorageError("SHA-256 of a reference cache payload: OpenSSL failed");
    }
    return to_hex({md, n});
}

}  // namespace tlsmon
