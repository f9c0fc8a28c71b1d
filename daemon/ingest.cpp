#include "daemon/ingest.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <new>

#include "core/utc_time.hpp"
#include "daemon/ingest_files.hpp"
#include "pipeline/epoch_files.hpp"
#include "pipeline/sha256.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

// A file whose bytes cannot be read has no content hash; it is identified by what can be
// seen of it (name, size, mtime), so the same unreadable file is recorded once.
std::string unreadable_identity(const fs::path& file) {
    struct stat st {};
    ::stat(file.c_str(), &st);
    return sha256_text("unreadable\n" + file.filename().string() + "\n" +
                       std::to_string(st.st_size) + "\n" + std::to_string(st.st_mtim.tv_sec));
}

std::int64_t size_of(const fs::path& file) {
    std::error_code ec;
    const auto n = fs::file_size(file, ec);
    return ec ? 0 : static_cast<std::int64_t>(n);
}

IngestOutcome record_unreadable(IngestContext& ctx, const fs::path& file,
                                const std::string& problem) {
    const std::string reason = "cannot read the file: " + problem;
    std::string used;
    NewEpoch row{unreadable_identity(file),
                 acquisition_time(file, {TimeSource::file_name, TimeSource::mtime}, used), file,
                 size_of(file), ctx.station};
    const EpochInsert ins = ctx.db.epochs().insert(row);
    if (!ins.inserted) return IngestOutcome::known;
    if (!ctx.db.epochs().claim(ins.id)) return IngestOutcome::known;
    const fs::path to =
        free_name(ctx.config.paths.quarantine, file.filename().string(), row.sha256.substr(0, 12));
    write_reason_file(to, file.string(), reason);
    ctx.db.epochs().fail(ins.id, reason, to.string());
    try {
        move_file(file, to);
        ctx.events.record(ctx.db, "error", "unreadable",
                          file.string() + ": " + reason + "; moved to " + to.string(), ins.id);
    } catch (const Error& e) {
        ctx.events.record(ctx.db, "error", "unreadable",
                          file.string() + ": " + reason + "; left in place (" + e.what() + ")",
                          ins.id);
    }
    return IngestOutcome::unreadable;
}

// A file that is no duplicate to delete (empty, or a copy of an epoch that failed) goes to
// quarantine with its reason; no new epoch (the content has one), a system event instead.
IngestOutcome quarantine_copy(IngestContext& ctx, const fs::path& file, const Epoch& epoch,
                              const std::string& reason) {
    return quarantine(ctx, file, epoch.sha256.substr(0, 12), reason, epoch.id);
}

// MemAvailable of /proc/meminfo in bytes; nullopt where it cannot be read.
std::optional<std::int64_t> available_memory() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::int64_t kib = 0;
    std::string unit;
    while (in >> key >> kib >> unit) {
        if (key == "MemAvailable:") return kib * 1024;
    }
    return std::nullopt;
}

std::string gib(std::int64_t bytes) {
    return fmt::format("{:.2f} GiB", static_cast<double>(bytes) / (1 << 30));
}

// Why a file of `size` bytes is not read at all ("" when it may be): files are read whole.
std::string too_large_to_read(std::int64_t size, const IngestConfig& config) {
    if (size > config.max_file_size) {
        return fmt::format("the file is {} ({} bytes), larger than ingest.max_file_size = {}",
                           gib(size), size, gib(config.max_file_size));
    }
    if (const auto available = available_memory(); available && size > *available) {
        return fmt::format(
            "the file is {} ({} bytes), more than the memory available to read it ({})", gib(size),
            size, gib(*available));
    }
    return "";
}

// The file has the content of an epoch that exists already.
IngestOutcome handle_known(IngestContext& ctx, const fs::path& file, const Epoch& epoch) {
    const bool same_path = fs::path(epoch.file_path) == file;
    // The content of an epoch that was never read, its own file gone (renamed, or deleted
    // and copied in again): the epoch takes this file rather than lose the content.
    std::error_code gone;
    const bool unread_and_gone = (epoch.status == EpochStatus::pending && !same_path &&
                                  !fs::exists(epoch.file_path, gone) && !gone) ||
                                 (epoch.status == EpochStatus::failed && !epoch.archive_path);
    if (unread_and_gone && ctx.db.epochs().relocate(epoch.id, file)) {
        spdlog::info("{}: the content of epoch {} ({}, {}); the epoch now takes this file",
                     file.string(), epoch.id, epoch.file_path, to_string(epoch.status));
        return IngestOutcome::known;
    }
    struct stat st {};
    const bool empty = ::lstat(file.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 0;
    if (!is_finished(epoch.status)) {
        if (same_path) return IngestOutcome::known;  // queued already (e.g. after a restart)
        if (empty) return quarantine_copy(ctx, file, epoch, "the file is empty");
        // Whether this is a duplicate or a copy of a broken file is known once the epoch
        // is processed.
        return IngestOutcome::wait_for_epoch;
    }
    // (Not for a scan the archive policy removed or re-encoded: its absence is intended.)
    if (epoch.archive_path && !fs::exists(*epoch.archive_path) &&
        fs::path(*epoch.archive_path).filename().string().starts_with(file.stem().string()) &&
        !ctx.db.archive().record(epoch.id)) {
        // The epoch was committed but the daemon stopped before moving its file: finish.
        try {
            move_file(file, *epoch.archive_path);
            spdlog::info("{}: moved to {} (epoch {} was {} before the restart)", file.string(),
                         *epoch.archive_path, epoch.id, to_string(epoch.status));
        } catch (const Error& e) {
            spdlog::warn("{}: epoch {} is {}, its file stays here: {}", file.string(), epoch.id,
                         to_string(epoch.status), e.what());
        }
        return IngestOutcome::known;
    }
    if (same_path && ctx.config.ingest.archive == ArchiveMode::keep) return IngestOutcome::known;
    if (empty) return quarantine_copy(ctx, file, epoch, "the file is empty");
    if (epoch.status == EpochStatus::failed) {
        return quarantine_copy(ctx, file, epoch,
                               "same content as epoch " + std::to_string(epoch.id) + " (" +
                                   epoch.file_path + "), which failed: " + epoch.reason);
    }
    const std::string what = file.string() + ": same content as epoch " + std::to_string(epoch.id) +
                             " (" + epoch.file_path + ", " + std::string(to_string(epoch.status)) +
                             "); duplicate ";
    if (ctx.config.ingest.archive == ArchiveMode::move) {
        std::error_code ec;
        fs::remove(file, ec);
        ctx.events.record(ctx.db, "info", "duplicate",
                          what + (ec ? "could not be removed: " + ec.message() : "removed"),
                          epoch.id);
    } else {
        ctx.events.record(ctx.db, "info", "duplicate", what + "left in place", epoch.id);
    }
    return IngestOutcome::duplicate;
}

}  // namespace

IngestOutcome quarantine(IngestContext& ctx, const fs::path& file, const std::string& tag,
                         const std::string& reason, std::optional<EpochId> epoch) {
    const fs::path to = free_name(ctx.config.paths.quarantine, file.filename().string(), tag);
    write_reason_file(to, file.string(), reason);
    try {
        move_file(file, to);
        ctx.events.record(ctx.db, "error", "quarantine",
                          file.string() + ": " + reason + "; moved to " + to.string(), epoch);
    } catch (const Error& e) {
        std::error_code ignored;
        fs::remove(to.string() + ".reason.txt", ignored);
        ctx.events.record(ctx.db, "error", "quarantine",
                          file.string() + ": " + reason + "; left in place (" + e.what() + ")",
                          epoch);
    }
    return IngestOutcome::quarantined;
}

namespace {

// The epoch this very file was recorded as, known without reading it: the same path and
// size, not modified since the epoch was recorded, and the epoch queued (or finished and
// kept in place). After a restart the files waiting in the ingest folder are not hashed
// again; the pipeline checks their sha256 when it reads them anyway. Anything else is
// hashed: a file is never removed as a duplicate on its name alone.
std::optional<Epoch> recorded_unchanged(IngestContext& ctx, const fs::path& file) {
    const auto epoch = ctx.db.epochs().find_by_file(file);
    if (!epoch || epoch->file_size != size_of(file)) return std::nullopt;
    const auto mtime = file_mtime(file);
    if (!mtime || *mtime >= epoch->discovered) return std::nullopt;  // same second: hash
    const bool queued =
        epoch->status == EpochStatus::pending || epoch->status == EpochStatus::processing;
    const bool kept =
        (epoch->status == EpochStatus::done || epoch->status == EpochStatus::rejected) &&
        ctx.config.ingest.archive == ArchiveMode::keep;
    if (!queued && !kept) return std::nullopt;
    return epoch;
}

}  // namespace

IngestOutcome ingest_file(IngestContext& ctx, const fs::path& file, EpochId* matched) {
    try {
        if (const auto epoch = recorded_unchanged(ctx, file)) {
            if (matched) *matched = epoch->id;
            return IngestOutcome::known;
        }
        const std::string refused = too_large_to_read(size_of(file), ctx.config.ingest);
        if (!refused.empty()) {
            return quarantine(ctx, file, unreadable_identity(file).substr(0, 12),
                              refused + "; not read", std::nullopt);
        }
        HashedBytes content;
        try {
            content = read_file_hashed(file);
        } catch (const FileAccessError& e) {
            if (e.error_number() == ENOENT) return IngestOutcome::known;  // gone meanwhile
            if (e.error_number() == ELOOP || e.error_number() == EINVAL) {
                // Replaced by a symbolic link (or a FIFO) since the watcher saw it: never
                // read through; the watcher reports the link.
                spdlog::warn("{}", e.what());
                return IngestOutcome::not_a_file;
            }
            return record_unreadable(ctx, file, e.what());
        }
        const std::string& sha = content.sha256;
        if (auto epoch = ctx.db.epochs().find_by_sha256(sha)) {
            if (matched) *matched = epoch->id;
            return handle_known(ctx, file, *epoch);
        }
        std::string used;
        const UtcSeconds acquired =
            acquisition_time(file, ctx.config.ingest.acquisition_time, used);
        const UtcSeconds now = now_utc();
        if (static_cast<double>(acquired - now) > ctx.config.ingest.max_clock_ahead) {
            return quarantine(
                ctx, file, sha.substr(0, 12),
                fmt::format("acquired {} (from {}), {} s after the daemon's clock ({}), more "
                            "than ingest.max_clock_ahead = {} s: a wrong scanner clock or file "
                            "name; not recorded as an epoch (correct the time and copy the file "
                            "back into the ingest folder)",
                            format_utc(acquired), used, acquired - now, format_utc(now),
                            ctx.config.ingest.max_clock_ahead),
                std::nullopt);
        }
        const EpochInsert ins =
            ctx.db.epochs().insert(NewEpoch{sha, acquired, file, size_of(file), ctx.station});
        if (matched) *matched = ins.id;
        if (!ins.inserted) {
            if (auto epoch = ctx.db.epochs().find(ins.id)) return handle_known(ctx, file, *epoch);
            return IngestOutcome::known;
        }
        spdlog::info("{}: new epoch {} (sha256 {}, acquired {} from {})", file.string(), ins.id,
                     sha.substr(0, 12), acquired, used);
        if (ctx.new_epoch_bytes) *ctx.new_epoch_bytes = std::move(content);
        return IngestOutcome::new_epoch;
    } catch (const StorageError& e) {
        ctx.events.record(
            ctx.db, "error", e.disk_full() ? "disk_full" : "database_error",
            file.string() + ": the database refused the new epoch, will retry: " + e.what());
        return IngestOutcome::retry_later;
    } catch (const std::bad_alloc&) {  // the size check passed, the memory went meanwhile
        return quarantine(
            ctx, file, unreadable_identity(file).substr(0, 12),
            fmt::format("not enough memory to read the file ({} bytes)", size_of(file)),
            std::nullopt);
    } catch (const std::exception& e) {  // e.g. the folder became unreadable
        spdlog::error("{}: {}; will retry", file.string(), e.what());
        return IngestOutcome::retry_later;
    }
}

}  // namespace tlsmon
