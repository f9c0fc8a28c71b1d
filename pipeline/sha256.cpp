#include "pipeline/sha256.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <vector>

#include "core/hex.hpp"

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
        return to_hex({md, n});
    }

  private:
    std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

}  // namespace

namespace {

constexpr std::size_t kChunk = 1 << 20;

// A scan file opened for reading. A symbolic link is not followed (ELOOP) and only a regular
// file is read (not a FIFO or device with a scan's name): only the folder's own files.
class InputFile {
  public:
    explicit InputFile(const std::filesystem::path& path) : path_(path) {
        fd_ = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
        if (fd_ < 0) {
            const int e = errno;
            throw FileAccessError(path.string() + ": cannot open: " +
                                      (e == ELOOP ? std::string("a symbolic link, not followed")
                                                  : std::string(std::strerror(e))),
                                  e);
        }
        struct stat st {};
        if (::fstat(fd_, &st) == 0 && !S_ISREG(st.st_mode)) {
            ::close(fd_);
            throw FileAccessError(path.string() + ": not a regular file", EINVAL);
        }
    }
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;
    ~InputFile() { ::close(fd_); }

    // Up to `n` bytes into `to`; 0 at the end of the file. Throws FileAccessError.
    std::size_t read(char* to, std::size_t n) {
        for (;;) {
            const ssize_t got = ::read(fd_, to, n);
            if (got >= 0) return static_cast<std::size_t>(got);
            if (errno == EINTR) continue;
            const int e = errno;
            throw FileAccessError(path_.string() + ": read error: " + std::strerror(e), e);
        }
    }
    FileStamp stamp() const {
        struct stat st {};
        if (::fstat(fd_, &st) != 0) return {};
        return {st.st_size, std::int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec};
    }

  private:
    const std::filesystem::path& path_;
    int fd_ = -1;
};

}  // namespace

FileStamp file_stamp(const std::filesystem::path& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) return {};
    return {st.st_size, std::int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec};
}

std::string sha256_file(const std::filesystem::path& path) {
    InputFile file(path);
    Digest digest;
    std::vector<char> buffer(kChunk);
    while (const std::size_t n = file.read(buffer.data(), buffer.size()))
        digest.update(buffer.data(), n);
    return digest.hex();
}

HashedBytes read_file_hashed(const std::filesystem::path& path) {
    InputFile file(path);
    Digest digest;
    HashedBytes out;
    out.stamp = file.stamp();
    // Read into the final buffer (sized from fstat, grown if the file grows meanwhile) and
    // hash each chunk right after it arrives.
    std::size_t used = 0;
    out.bytes.resize(static_cast<std::size_t>(std::max<std::int64_t>(out.stamp.size, 0)) + 1);
    for (;;) {
        if (used == out.bytes.size()) out.bytes.resize(out.bytes.size() * 2);
        const std::size_t n =
            file.read(out.bytes.data() + used, std::min(kChunk, out.bytes.size() - used));
        if (n == 0) break;
        digest.update(out.bytes.data() + used, n);
        used += n;
    }
    out.bytes.resize(used);
    out.sha256 = digest.hex();
    return out;
}

std::string sha256_text(const std::string& bytes) {
    Digest digest;
    digest.update(bytes.data(), bytes.size());
    return digest.hex();
}

}  // namespace tlsmon
