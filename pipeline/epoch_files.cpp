#include "pipeline/epoch_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "core/text_escape.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

fs::path free_name(const fs::path& folder, const std::string& name, const std::string& tag) {
    fs::path candidate = folder / name;
    if (!fs::exists(candidate)) return candidate;
    const fs::path n(name);
    const std::string stem = n.stem().string();
    const std::string ext = n.extension().string();
    for (int i = 1;; ++i) {
        std::string free = stem + "." + tag;
        if (i > 1) free.append("-").append(std::to_string(i));
        candidate = folder / (free + ext);
        if (!fs::exists(candidate)) return candidate;
    }
}

namespace {

void sync_folder(const fs::path& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
}

// Copies the regular file `from` (not through a symbolic link) to `to` and syncs the copy.
std::error_code copy_and_sync(const fs::path& from, const fs::path& to) {
    const auto fail = [](int e) { return std::error_code(e, std::generic_category()); };
    const int in = ::open(from.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (in < 0) return fail(errno);
    const int out = ::open(to.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (out < 0) {
        const int e = errno;
        ::close(in);
        return fail(e);
    }
    std::error_code ec;
    std::vector<char> buffer(1 << 20);
    for (;;) {
        const ssize_t n = ::read(in, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            ec = fail(errno);
            break;
        }
        if (n == 0) break;
        for (ssize_t done = 0; done < n && !ec;) {
            const ssize_t w =
                ::write(out, buffer.data() + done, static_cast<std::size_t>(n - done));
            if (w < 0 && errno == EINTR) continue;
            if (w < 0) {
                ec = fail(errno);
            } else {
                done += w;
            }
        }
        if (ec) break;
    }
    // The source is removed after the copy: the copy must be on disk first.
    if (!ec && ::fsync(out) != 0) ec = fail(errno);
    if (::close(out) != 0 && !ec) ec = fail(errno);
    ::close(in);
    return ec;
}

}  // namespace

void move_file(const fs::path& from, const fs::path& to) {
    if (::rename(from.c_str(), to.c_str()) == 0) {
        sync_folder(to.parent_path());
        return;
    }
    if (errno != EXDEV) {
        throw Error("cannot move " + from.string() + " to " + to.string() + ": " +
                    std::strerror(errno));
    }
    // Another file system: copy to a temporary name, sync, rename, then remove the source.
    // The source is opened without following a symbolic link (never read through one).
    const fs::path tmp = to.parent_path() / ("." + to.filename().native() + ".part");
    std::error_code ec = copy_and_sync(from, tmp);
    if (!ec) fs::rename(tmp, to, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw Error("cannot copy " + from.string() + " to " + to.string() + ": " + ec.message());
    }
    sync_folder(to.parent_path());
    fs::remove(from, ec);
}

bool write_reason_file(const fs::path& file, const std::string& original,
                       const std::string& reason) {
    // Two lines whatever the names hold: control characters escaped.
    const std::string text = "file: " + escape_control_characters(original) +
                             "\nreason: " + escape_control_characters(reason) + "\n";
    const int fd = ::open((file.string() + ".reason.txt").c_str(),
                          O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) return false;
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
    }
    return ::close(fd) == 0 && done == text.size();
}

}  // namespace tlsmon
