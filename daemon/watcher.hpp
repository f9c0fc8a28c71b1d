#pragma once
// Watching the ingest folder for complete scan files. inotify (inotify(7)) reports
// close-after-write and moved-in; a full scan at start and every rescan_interval catches
// what inotify misses (network shares, events lost while the queue overflowed).
//
// A file is complete when
//   - it is not being written: no IN_CREATE/IN_MODIFY since its last IN_CLOSE_WRITE or
//     IN_MOVED_TO (a file only found by a scan counts as closed), and
//   - its size and mtime have not changed for stable_seconds, and
//   - no process has it open for writing (held_open_for_writing): a file found by a scan
//     after a restart while its writer pauses is waited for, not taken half-written.
// Meteo sidecars (`<scan stem>.meteo.csv`) are watched the same way, never as scans.
// Hidden and temporary names (".x.part", "x.tmp", "x~") and other extensions are ignored.
// Only regular files are taken. A symbolic link, a folder, a FIFO or any other entry that
// is not a regular file, with a scan's name, is never followed nor read nor tracked: it is
// reported once (take_not_files) and left where it is.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "config/config.hpp"

namespace tlsmon {

using SteadyTime = std::chrono::steady_clock::time_point;

// Whether `name` looks like a scan the daemon should take (extension, not hidden/temporary,
// not a meteo sidecar whatever the extensions list).
bool is_scan_name(const std::string& name, const std::vector<std::string>& extensions);

// Whether some process has `path` open for writing. A read lease (fcntl F_SETLEASE) cannot
// be taken while any process, of any user, has the file open for writing; where no lease
// can be taken (another user's file without CAP_LEASE, a file system without leases), the
// open files of the processes this one may inspect (/proc/<pid>/fd and fdinfo).
bool held_open_for_writing(const std::filesystem::path& path);
// The /proc part alone (tests).
bool held_open_for_writing_by_proc(const std::filesystem::path& path);

struct NotAFile {
    std::filesystem::path path;
    std::string kind;  // "symbolic link", "folder", "FIFO (named pipe)", "socket", "device"
};

struct GrowingFile {
    std::filesystem::path path;
    double seconds = 0;  // since first seen
    std::int64_t size = 0;
};

class FolderWatcher {
  public:
    FolderWatcher(std::filesystem::path folder, IngestConfig config);  // throws Error
    ~FolderWatcher();
    FolderWatcher(const FolderWatcher&) = delete;
    FolderWatcher& operator=(const FolderWatcher&) = delete;

    int fd() const { return inotify_fd_; }
    void set_config(const IngestConfig& config) { config_ = config; }

    // Drains the pending inotify events (non-blocking).
    void read_events(SteadyTime now);
    // Lists the folder and adds every scan file not yet handed out.
    void rescan(SteadyTime now);
    // Files complete now; they are handed out once (until their size or mtime changes, or
    // forget() is called). `growing` receives, once per file, those still not complete
    // after max_growing.
    std::vector<std::filesystem::path> take_complete(SteadyTime now,
                                                     std::vector<GrowingFile>& growing);
    // Entries with a scan's name that are no regular file, seen since the last call, each
    // once (again only after it was removed or replaced).
    std::vector<NotAFile> take_not_files();
    // Hand the file out again at the next rescan (e.g. the database was full).
    void forget(const std::filesystem::path& path);

    bool has_candidates() const { return !candidates_.empty(); }
    // Whether `path` is tracked and not yet complete (nor reported as growing).
    bool is_waiting_for(const std::filesystem::path& path) const;
    // Candidates not yet reported as growing past max_growing (`--once` waits for these).
    bool has_candidates_in_time() const;
    // When the next stability check is worth doing (now if nothing is tracked: none needed).
    std::chrono::steady_clock::duration until_next_check(SteadyTime now) const;

  private:
    struct Candidate {
        std::int64_t size = -1;
        std::int64_t mtime_ns = -1;
        SteadyTime first_seen;
        SteadyTime last_change;
        bool writing = false;
        bool reported_growing = false;
        bool reported_open = false;
    };
    struct Handed {
        std::int64_t size = -1;
        std::int64_t mtime_ns = -1;
    };

    bool add_watch();  // false (errno set) if the folder cannot be watched
    void touch(const std::string& name, SteadyTime now, bool writing, bool closed);
    void note_not_a_file(const std::string& name, std::uint64_t inode, const char* kind);

    std::filesystem::path folder_;
    IngestConfig config_;
    int inotify_fd_ = -1;
    std::map<std::string, Candidate> candidates_;
    std::map<std::string, Handed> handed_;
    std::map<std::string, std::uint64_t> not_files_;  // name -> inode of the entry, reported
    std::vector<NotAFile> new_not_files_;
};

}  // namespace tlsmon
