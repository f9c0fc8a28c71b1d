#include "pipeline/sha256.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <vector>

namespace tlsmon {

namespace {

// OpenSSL's EVP interface (libcrypto) computes the digest; only the hex text is ours.
class Digest {
  public:
    Digest() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
        if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1) {
            throw Error("SHA-256: OpenSSL could not initialise the digest");
        }
    }
    void update(const void* data, std::size_t n) {
        if (EVP_DigestUpdate(ctx_.get(), data, n) != 1) throw Error("SHA-256: update failed");
    }
    std::string hex() {
        unsigned char md[EVP_MAX_MD_SIZE];
        unsigned int n = 0;
        if (EVP_DigestFinal_ex(ctx_.get(), md, &n) != 1) throw Error("SHA-256: final failed");
        static const char* digits = "0123456789abcdef";
        std::string out;
        for (unsigned int i = 0; i < n; ++i) {
            out += digits[md[i] >> 4];
            out += digits[md[i] & 15];
        }
        return out;
    }

  private:
    std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

}  // namespace

namespace {

// Reads the whole file in 1 MiB chunks, handing each to `take`; `size` first gets the
// file's size. A symbolic link is not followed (ELOOP): only the folder's own files are
// read. Throws FileAccessError.
template <typename Size, typename Take>
void read_chunks(const std::filesystem::path& path, Size&& size, Take&& take) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int e = errno;
        throw FileAccessError(path.string() + ": cannot open: " +
                                  (e == ELOOP ? std::string("a symbolic link, not followed")
                                              : std::string(std::strerror(e))),
                              e);
    }
    struct stat st {};
    if (::fstat(fd, &st) == 0) {
        if (!S_ISREG(st.st_mode)) {  // a FIFO or device with a scan's name
            ::close(fd);
            throw FileAccessError(path.string() + ": not a regular file", EINVAL);
        }
        size(static_cast<std::size_t>(st.st_size));
    }
    std::vector<char> buffer(1 << 20);
    for (;;) {
        const ssize_t n = ::read(fd, buffer.data(), buffer.size());
        if (n == 0) break;
        if (n < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            ::close(fd);
            throw FileAccessError(path.string() + ": read error: " + std::strerror(e), e);
        }
        take(buffer.data(), static_cast<std::size_t>(n));
    }
    ::close(fd);
}

}  // namespace

std::string sha256_file(const std::filesystem::path& path) {
    Digest digest;
    read_chunks(
        path, [](std::size_t) {}, [&](const char* data, std::size_t n) { digest.update(data, n); });
    return digest.hex();
}

std::string read_file_bytes(const std::filesystem::path& path) {
    std::string bytes;
    read_chunks(
        path, [&](std::size_t size) { bytes.reserve(size); },
        [&](const char* data, std::size_t n) { bytes.append(data, n); });
    return bytes;
}

std::string sha256_text(const std::string& bytes) {
    Digest digest;
    digest.update(bytes.data(), bytes.size());
    return digest.hex();
}

}  // namespace tlsmon
