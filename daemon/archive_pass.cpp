#include "daemon/archive_pass.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <span>

#include "daemon/scan_reencoding.hpp"

namespace fs = std::filesystem;

namespace tlsmon {

namespace {

// Deletes `path` if it is there; its size when it was deleted, 0 when it was not there, an
// entry in `errors` when it could not be deleted.
std::int64_t delete_file(const std::string& path, std::vector<std::string>& errors) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) return 0;  // gone already
    if (!fs::remove(path, ec) || ec) {
        errors.push_back(path + ": not deleted: " + (ec ? ec.message() : "not found"));
        return 0;
    }
    return static_cast<std::int64_t>(size);
}

// One pass at a time over a folder (the daemon's and `tlsmon archive run`): an exclusive
// flock on `<folder>/.archive-pass.lock`, released when the pass ends or its process dies.
class PassLock {
  public:
    explicit PassLock(const fs::path& folder) {
        const fs::path file = folder / ".archive-pass.lock";
        fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
        if (fd_ < 0) {
            why_ = file.string() + ": " + std::strerror(errno);
        } else if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            why_ = errno == EWOULDBLOCK ? "another archive pass is running (" + file.string() + ")"
                                        : file.string() + ": " + std::strerror(errno);
        }
    }
    ~PassLock() {
        if (fd_ >= 0) ::close(fd_);
    }
    PassLock(const PassLock&) = delete;
    PassLock& operator=(const PassLock&) = delete;
    const std::string& why_not() const { return why_; }

  private:
    int fd_ = -1;
    std::string why_;
};

// E57 files a killed pass was writing (`<stem>.e57.part`): only a pass writes such names, and
// none other runs (PassLock).
void delete_partial_files(const fs::path& folder, ArchivePassResult& r) {
    std::error_code ec;
    for (const auto& f : fs::directory_iterator(folder, ec)) {
        const std::string name = f.path().filename().string();
        if (name.ends_with(".e57.part")) r.bytes_freed += delete_file(f.path().string(), r.errors);
    }
}

}  // namespace

ArchivePassResult run_archive_pass(EpochDatabase& db, const ArchivePolicy& policy,
                                   const fs::path& folder, const std::function<bool()>& stop) {
    auto& store = db.archive();
    ArchivePassResult r;
    const PassLock lock(folder);
    if (!lock.why_not().empty()) {
        r.errors.push_back("not run: " + lock.why_not());
        r.stopped = true;
        return r;
    }
    delete_partial_files(folder, r);
    for (const auto& path : store.files_to_delete()) {
        if (const auto bytes = delete_file(path, r.errors); bytes > 0) {
            ++r.deletions_finished;
            r.bytes_freed += bytes;
        }
    }
    r.plan = store.plan(folder, policy);
    const std::span<const ArchivedScan> remove(r.plan.remove);
    const auto batch = static_cast<std::size_t>(std::max(1, policy.batch_scans));
    for (std::size_t at = 0; at < remove.size() && !r.stopped; at += batch) {
        if ((r.stopped = stop())) break;
        const auto recorded = store.record_removed(
            remove.subspan(at, std::min(batch, remove.size() - at)), now_utc());
        for (const auto& scan : recorded) r.bytes_freed += delete_file(scan.path, r.errors);
        r.scans_removed += static_cast<std::int64_t>(recorded.size());
    }
    for (const auto& scan : r.plan.reencode) {
        if (r.stopped || (r.stopped = stop())) break;
        // A file left by a pass killed between writing the E57 and recording it.
        const fs::path leftover = fs::path(scan.path).replace_extension(".e57");
        if (fs::exists(leftover) && !store.file_in_use(leftover)) {
            r.bytes_freed += delete_file(leftover.string(), r.errors);
        }
        try {
            const auto written = reencode_as_e57(scan.path, scan.sha256, policy.e57_resolution);
            store.record_reencoded(scan, written.path, written.bytes, written.sha256, now_utc());
            ++r.scans_reencoded;
            r.reencoded_bytes_before += scan.bytes;
            r.reencoded_bytes_after += written.bytes;
            r.bytes_freed += delete_file(scan.path, r.errors) - written.bytes;
        } catch (const Error& e) {
            // Recorded, so the next pass does not try again (a warning event names it).
            store.record_not_reencoded(scan, e.what(), now_utc());
            r.errors.push_back(e.what());
        }
    }
    if (r.scans_reencoded > 0) {
        db.events().record({now_utc(), "info", "archive_reencoded",
                            std::to_string(r.scans_reencoded) +
                                " archived scans re-encoded as E57 by the archive "
                                "policy: " +
                                std::to_string(r.reencoded_bytes_before) + " -> " +
                                std::to_string(r.reencoded_bytes_after) + " bytes",
                            std::nullopt});
    }
    return r;
}

}  // namespace tlsmon
