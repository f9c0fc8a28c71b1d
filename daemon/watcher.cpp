#include "daemon/watcher.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <utility>

#include "core/error.hpp"
#include "formats/meteo_csv.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

bool is_scan_name(const std::string& name, const std::vector<std::string>& extensions) {
    if (name.empty() || name.front() == '.' || name.back() == '~') return false;
    if (is_meteo_sidecar_name(name)) return false;
    const auto dot = name.rfind('.');
    if (dot == std::string::npos || dot == 0) return false;
    std::string ext = name.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == "part" || ext == "tmp" || ext == "partial") return false;
    return std::find(extensions.begin(), extensions.end(), ext) != extensions.end();
}

namespace {

struct FileState {
    bool exists = false;
    bool regular = false;
    bool symlink = false;
    const char* kind = "";  // what it is when not a regular file
    std::uint64_t inode = 0;
    std::int64_t size = -1;
    std::int64_t mtime_ns = -1;
};

// The folder entry itself: a symbolic link is not followed.
FileState stat_file(const fs::path& p) {
    struct stat st {};
    FileState s;
    if (::lstat(p.c_str(), &st) != 0) return s;
    s.exists = true;
    s.regular = S_ISREG(st.st_mode);
    s.symlink = S_ISLNK(st.st_mode);
    s.kind = s.symlink                                    ? "symbolic link"
             : S_ISDIR(st.st_mode)                        ? "folder"
             : S_ISFIFO(st.st_mode)                       ? "FIFO (named pipe)"
             : S_ISSOCK(st.st_mode)                       ? "socket"
             : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "device"
                                                          : "special file";
    s.inode = st.st_ino;
    s.size = st.st_size;
    s.mtime_ns = std::int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec;
    return s;
}

// A lease break notifies the holder with SIGIO, whose default action ends the process; the
// lease is only held for the instant of the check, the notification is of no use.
void ignore_lease_break_signal() {
    static std::once_flag once;
    std::call_once(once, [] { std::signal(SIGIO, SIG_IGN); });
}

// true/false: open for writing or not; nullopt: no lease can be taken here.
std::optional<bool> open_for_writing_by_lease(const fs::path& path) {
    ignore_lease_break_signal();
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    std::optional<bool> open_for_writing;
    if (::fcntl(fd, F_SETLEASE, F_RDLCK) == 0) {
        ::fcntl(fd, F_SETLEASE, F_UNLCK);
        open_for_writing = false;
    } else if (errno == EAGAIN) {  // a writer (or a write lease) exists
        open_for_writing = true;
    }  // EACCES (not the owner), EINVAL (no leases on this file system): cannot tell
    ::close(fd);
    return open_for_writing;
}

bool all_digits(const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

// The access mode in /proc/<pid>/fdinfo/<fd> ("flags:\t0100002", octal).
std::optional<int> fd_access_mode(const fs::path& fdinfo) {
    std::ifstream in(fdinfo);
    std::string key;
    while (in >> key) {
        if (key == "flags:") {
            unsigned long flags = 0;
            if (!(in >> std::oct >> flags)) return std::nullopt;
            return static_cast<int>(flags & O_ACCMODE);
        }
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return std::nullopt;
}

}  // namespace

bool held_open_for_writing_by_proc(const fs::path& path) {
    struct stat target {};
    if (::lstat(path.c_str(), &target) != 0 || !S_ISREG(target.st_mode)) return false;
    std::error_code ec;
    for (fs::directory_iterator p("/proc", ec), end; !ec && p != end; p.increment(ec)) {
        if (!all_digits(p->path().filename().string())) continue;
        std::error_code fd_ec;  // another user's process: not visible, skipped
        for (fs::directory_iterator f(p->path() / "fd", fd_ec), fend; !fd_ec && f != fend;
             f.increment(fd_ec)) {
            struct stat st {};
            if (::stat(f->path().c_str(), &st) != 0) continue;
            if (st.st_dev != target.st_dev || st.st_ino != target.st_ino) continue;
            const auto mode = fd_access_mode(p->path() / "fdinfo" / f->path().filename());
            if (!mode || *mode != O_RDONLY) return true;
        }
    }
    return false;
}

bool held_open_for_writing(const fs::path& path) {
    if (const auto by_lease = open_for_writing_by_lease(path)) return *by_lease;
    return held_open_for_writing_by_proc(path);
}

FolderWatcher::FolderWatcher(fs::path folder, IngestConfig config)
    : folder_(std::move(folder)), config_(std::move(config)) {
    inotify_fd_ = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (inotify_fd_ < 0) throw Error(std::string("inotify_init1: ") + std::strerror(errno));
    if (!add_watch()) {
        const int e = errno;
        ::close(inotify_fd_);
        throw Error(folder_.string() + ": cannot watch the ingest folder: " + std::strerror(e));
    }
}

bool FolderWatcher::add_watch() {
    const std::uint32_t mask = IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_MODIFY | IN_DELETE |
                               IN_MOVED_FROM | IN_ONLYDIR;
    return ::inotify_add_watch(inotify_fd_, folder_.c_str(), mask) >= 0;
}

FolderWatcher::~FolderWatcher() {
    ::close(inotify_fd_);
}

void FolderWatcher::touch(const std::string& name, SteadyTime now, bool writing, bool closed) {
    if (!is_scan_name(name, config_.extensions) && !is_meteo_sidecar_name(name)) return;
    const fs::path path = folder_ / name;
    const FileState st = stat_file(path);
    if (!st.exists) return;
    if (!st.regular) {
        note_not_a_file(name, st.inode, st.kind);
        return;
    }
    if (auto h = handed_.find(name); h != handed_.end()) {
        if (h->second.size == st.size && h->second.mtime_ns == st.mtime_ns) return;
        handed_.erase(h);  // new content under a known name: a new candidate
    }
    auto [it, added] = candidates_.try_emplace(name);
    Candidate& c = it->second;
    if (added) {
        c.first_seen = now;
        c.last_change = now;
        c.size = st.size;
        c.mtime_ns = st.mtime_ns;
    }
    if (writing) c.writing = true;
    if (closed) c.writing = false;
}

void FolderWatcher::note_not_a_file(const std::string& name, std::uint64_t inode,
                                    const char* kind) {
    candidates_.erase(name);
    handed_.erase(name);
    auto [it, added] = not_files_.try_emplace(name, inode);
    if (!added && it->second == inode) return;  // reported already
    it->second = inode;
    new_not_files_.push_back({folder_ / name, kind});
}

std::vector<NotAFile> FolderWatcher::take_not_files() {
    return std::exchange(new_not_files_, {});
}

void FolderWatcher::read_events(SteadyTime now) {
    alignas(inotify_event) char buffer[16384];
    for (;;) {
        const ssize_t n = ::read(inotify_fd_, buffer, sizeof buffer);
        if (n <= 0) {
            if (n < 0 && errno == EINTR) continue;
            break;
        }
        for (ssize_t off = 0; off < n;) {
            const auto* ev = reinterpret_cast<const inotify_event*>(buffer + off);
            off += static_cast<ssize_t>(sizeof(inotify_event) + ev->len);
            if (ev->mask & IN_Q_OVERFLOW) {
                spdlog::warn("{}: inotify queue overflowed; rescanning", folder_.string());
                // Close events may be lost: from now on only a stable size and mtime
                // tell when these files are complete, as for a file found by a scan.
                for (auto& [name, c] : candidates_) c.writing = false;
                rescan(now);
                continue;
            }
            if (ev->mask & IN_IGNORED) {  // the folder was deleted or moved away
                spdlog::warn("{}: the ingest folder is gone; watched again once it is back",
                             folder_.string());
                continue;
            }
            if (ev->len == 0) continue;
            const std::string name(ev->name);
            if (ev->mask & (IN_DELETE | IN_MOVED_FROM)) {
                candidates_.erase(name);
                handed_.erase(name);
                not_files_.erase(name);
            } else if (ev->mask & (IN_CLOSE_WRITE | IN_MOVED_TO)) {
                touch(name, now, false, true);
            } else if (ev->mask & (IN_CREATE | IN_MODIFY)) {
                touch(name, now, true, false);
            }
        }
    }
}

void FolderWatcher::rescan(SteadyTime now) {
    // The same watch if the folder is still there; a new one if it was deleted and created
    // again (the old watch ended with the folder: no events came since).
    add_watch();
    std::error_code ec;
    for (fs::directory_iterator it(folder_, ec), end; !ec && it != end; it.increment(ec)) {
        touch(it->path().filename().string(), now, false, false);
    }
    if (ec) spdlog::warn("{}: cannot list the ingest folder: {}", folder_.string(), ec.message());
    // Forget handed-out names whose file is gone (moved to the archive).
    for (auto it = handed_.begin(); it != handed_.end();) {
        it = stat_file(folder_ / it->first).exists ? std::next(it) : handed_.erase(it);
    }
    for (auto it = not_files_.begin(); it != not_files_.end();) {
        const FileState st = stat_file(folder_ / it->first);
        it = st.exists && !st.regular ? std::next(it) : not_files_.erase(it);
    }
}

std::vector<fs::path> FolderWatcher::take_complete(SteadyTime now,
                                                   std::vector<GrowingFile>& growing) {
    std::vector<fs::path> complete;
    const auto stable = std::chrono::duration<double>(config_.stable_seconds);
    const auto max_growing = std::chrono::duration<double>(config_.max_growing);
    for (auto it = candidates_.begin(); it != candidates_.end();) {
        Candidate& c = it->second;
        const fs::path path = folder_ / it->first;
        const FileState st = stat_file(path);
        if (!st.exists || !st.regular) {
            it = candidates_.erase(it);
            continue;
        }
        if (st.size != c.size || st.mtime_ns != c.mtime_ns) {
            c.size = st.size;
            c.mtime_ns = st.mtime_ns;
            c.last_change = now;
        }
        if (!c.writing && now - c.last_change >= stable) {
            if (!held_open_for_writing(path)) {
                complete.push_back(path);
                handed_[it->first] = Handed{st.size, st.mtime_ns};
                it = candidates_.erase(it);
                continue;
            }
            // Stable but still open (e.g. found by the scan at a restart while its writer
            // pauses): not complete; checked again stable_seconds later.
            c.last_change = now;
            if (!c.reported_open) {
                c.reported_open = true;
                spdlog::info("{}: still open for writing; waiting until it is closed",
                             path.string());
            }
        }
        if (!c.reported_growing && now - c.first_seen >= max_growing) {
            c.reported_growing = true;
            growing.push_back(GrowingFile{
                path, std::chrono::duration<double>(now - c.first_seen).count(), st.size});
        }
        ++it;
    }
    return complete;
}

bool FolderWatcher::has_candidates_in_time() const {
    return std::any_of(candidates_.begin(), candidates_.end(),
                       [](const auto& c) { return !c.second.reported_growing; });
}

bool FolderWatcher::is_waiting_for(const fs::path& path) const {
    const auto c = candidates_.find(path.filename().string());
    return c != candidates_.end() && path.parent_path() == folder_ && !c->second.reported_growing;
}

void FolderWatcher::forget(const fs::path& path) {
    handed_.erase(path.filename().string());
}

std::chrono::steady_clock::duration FolderWatcher::until_next_check(SteadyTime now) const {
    using namespace std::chrono;
    // Check often enough to see a file become stable soon after stable_seconds, but not
    // busily: a quarter of stable_seconds, between 50 ms and 1 s.
    const auto step = duration_cast<steady_clock::duration>(
        duration<double>(std::clamp(config_.stable_seconds / 4.0, 0.05, 1.0)));
    if (candidates_.empty()) return hours(1);
    steady_clock::duration best = hours(1);
    for (const auto& [name, c] : candidates_) {
        const auto due = c.last_change + duration_cast<steady_clock::duration>(
                                             duration<double>(config_.stable_seconds));
        best = std::min(best, due > now ? due - now : steady_clock::duration::zero());
    }
    return std::clamp(best, steady_clock::duration(milliseconds(50)), step);
}

}  // namespace tlsmon
