#include "daemon/ingest_meteo.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>

#include "core/utc_time.hpp"
#include "formats/meteo_csv.hpp"
#include "pipeline/epoch_files.hpp"
#include "pipeline/sha256.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kSuffix = ".meteo.csv";

SteadyTime after(SteadyTime now, double seconds) {
    return now +
           std::chrono::duration_cast<SteadyTime::duration>(std::chrono::duration<double>(seconds));
}

// The sidecar's content hash, or for a file that cannot be read one of its name, as for an
// unreadable scan. nullopt when it is gone or is no regular file.
std::optional<std::string> identity(const fs::path& sidecar) {
    std::error_code size_error;
    const auto size = fs::file_size(sidecar, size_error);
    if (!size_error && size > static_cast<std::uintmax_t>(kMaxMeteoSidecarBytes)) {
        // Not hashed (minutes for a large sparse file): as read_epoch_meteo names it.
        return sha256_text("too large\n" + sidecar.filename().string() + "\n" +
                           std::to_string(size));
    }
    try {
        return sha256_file(sidecar);
    } catch (const FileAccessError& e) {
        if (e.error_number() == ENOENT) return std::nullopt;
        if (e.error_number() == ELOOP || e.error_number() == EINVAL) {
            spdlog::warn("{}", e.what());
            return std::nullopt;
        }
        return sha256_text("unreadable\n" + sidecar.filename().string());
    }
}

void move_recorded(IngestContext& ctx, const fs::path& sidecar, const MeteoSidecar& m,
                   const std::string& what) {
    if (!m.path) {
        ctx.events.record(ctx.db, "warning", "meteo_" + std::string(to_string(m.outcome)),
                          what + "; left in place", m.epoch);
        return;
    }
    try {
        move_file(sidecar, *m.path);
        ctx.events.record(ctx.db, "warning", "meteo_" + std::string(to_string(m.outcome)),
                          what + "; moved to " + *m.path, m.epoch);
    } catch (const Error& e) {
        ctx.events.record(ctx.db, "warning", "meteo_" + std::string(to_string(m.outcome)),
                          what + "; could not be moved to " + *m.path + ": " + e.what(), m.epoch);
    }
}

// A sidecar recorded before (by its sha256 and name).
void handle_known(IngestContext& ctx, const fs::path& sidecar, const MeteoSidecar& known) {
    if (!known.path || fs::path(*known.path) == sidecar) return;  // it stays where it is
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(*known.path, ec))) {
        // Recorded, but the daemon stopped before moving it: finish.
        try {
            move_file(sidecar, *known.path);
            spdlog::info("{}: moved to {} (recorded as {} before the restart)", sidecar.string(),
                         *known.path, to_string(known.outcome));
        } catch (const Error& e) {
            spdlog::warn("{}: stays here: {}", sidecar.string(), e.what());
        }
        return;
    }
    std::string what =
        sidecar.string() + ": same content as the meteo sidecar at " + *known.path + "; duplicate ";
    if (ctx.config.ingest.archive == ArchiveMode::move) {
        fs::remove(sidecar, ec);
        what += ec ? "could not be removed: " + ec.message() : "removed";
    } else {
        what += "left in place";
    }
    ctx.events.record(ctx.db, "info", "duplicate", what, known.epoch);
}

// A sidecar whose epoch was processed already: recorded as unused, beside its scan.
void record_unused(IngestContext& ctx, const fs::path& sidecar, const std::string& sha,
                   const Epoch& epoch) {
    MeteoSidecar m;
    m.epoch = epoch.id;
    m.outcome = MeteoOutcome::unused;
    m.file_name = sidecar.filename().string();
    m.sha256 = sha;
    const auto records = ctx.db.meteo().of_epoch(epoch.id);
    const auto with = std::find_if(records.begin(), records.end(), [](const MeteoSidecar& r) {
        return r.outcome == MeteoOutcome::used || r.outcome == MeteoOutcome::rejected;
    });
    const std::string of_epoch = "epoch " + std::to_string(epoch.id) + " (" + epoch.file_path + ")";
    if (with != records.end()) {
        m.reason = of_epoch + " was processed with the meteo sidecar " + with->file_name +
                   " (sha256 " + with->sha256.substr(0, 12) + ") already";
    } else if (epoch.status == EpochStatus::failed) {
        m.reason = of_epoch + " failed: " + epoch.reason;
    } else {
        m.reason = "came after " + of_epoch + " was processed without meteo";
    }
    if (ctx.config.ingest.archive == ArchiveMode::move) {
        // Beside the scan, wherever it went (archive or quarantine).
        const fs::path folder = epoch.archive_path ? fs::path(*epoch.archive_path).parent_path()
                                                   : ctx.config.paths.archive;
        const std::string name =
            epoch.archive_path
                ? fs::path(*epoch.archive_path).stem().string() + std::string(kSuffix)
                : m.file_name;
        m.path = free_name(folder, name, sha.substr(0, 12)).string();
        // Beside a quarantined scan, with its reason as every file there.
        if (folder == ctx.config.paths.quarantine)
            write_reason_file(*m.path, sidecar.string(), m.reason);
    }
    // The record first, then the move: after a stop in between, take() finishes the move.
    ctx.db.meteo().record(m);
    move_recorded(ctx, sidecar, m, sidecar.string() + ": meteo sidecar not used: " + m.reason);
}

void record_orphan(IngestContext& ctx, const fs::path& sidecar, const std::string& sha) {
    MeteoSidecar m;
    m.outcome = MeteoOutcome::orphan;
    m.file_name = sidecar.filename().string();
    m.sha256 = sha;
    m.reason = "no scan " + m.file_name.substr(0, m.file_name.size() - kSuffix.size()) +
               ".* came within meteo.orphan_seconds = " +
               std::to_string(static_cast<long long>(ctx.config.meteo.orphan_seconds)) + " s";
    const fs::path to = free_name(ctx.config.paths.quarantine, m.file_name, sha.substr(0, 12));
    write_reason_file(to, sidecar.string(), m.reason);
    m.path = to.string();
    ctx.db.meteo().record(m);
    move_recorded(ctx, sidecar, m, sidecar.string() + ": orphan meteo sidecar: " + m.reason);
}

}  // namespace

void MeteoSidecars::settle(IngestContext& ctx, const fs::path& sidecar, SteadyTime now,
                           bool may_be_orphan) {
    try {
        const auto sha = identity(sidecar);
        if (!sha) {
            ready_.erase(sidecar);
            return;
        }
        const std::string name = sidecar.filename().string();
        if (const auto known = ctx.db.meteo().find(*sha, name)) {
            ready_.erase(sidecar);
            handle_known(ctx, sidecar, *known);
            return;
        }
        const std::string stem = name.substr(0, name.size() - kSuffix.size());
        const auto epoch = ctx.db.meteo().scan_epoch(sidecar.parent_path(), stem);
        if (epoch && is_finished(epoch->status)) {
            ready_.erase(sidecar);
            record_unused(ctx, sidecar, *sha, *epoch);
            return;
        }
        if (!epoch && may_be_orphan) {
            ready_.erase(sidecar);
            record_orphan(ctx, sidecar, *sha);
            return;
        }
    } catch (const StorageError& e) {
        ctx.events.record(ctx.db, "error", e.disk_full() ? "disk_full" : "database_error",
                          sidecar.string() + ": " + e.what() + "; will retry");
    }
    // Its epoch is pending or not there yet: ready for it, and looked at again as a
    // possible orphan after meteo.orphan_seconds.
    ready_[sidecar] = after(now, ctx.config.meteo.orphan_seconds);
}

void MeteoSidecars::take(IngestContext& ctx, const fs::path& sidecar, SteadyTime now) {
    settle(ctx, sidecar, now, false);
}

MeteoSidecars::Pairing MeteoSidecars::pair(const Epoch& epoch, const MeteoConfig& config,
                                           const FolderWatcher& watcher, SteadyTime now) const {
    const fs::path sidecar = meteo_sidecar_of(epoch.file_path);
    if (ready_.count(sidecar)) return {true, sidecar, std::nullopt};
    // There and still being written: worth waiting for, even past the deadline (e.g. found
    // by the folder scan after a restart, not yet known to be complete).
    if (watcher.is_waiting_for(sidecar)) return {false, std::nullopt, after(now, 1.0)};
    const double left = static_cast<double>(epoch.discovered) + config.wait_seconds -
                        static_cast<double>(now_utc());
    if (left <= 0) return {true, std::nullopt, std::nullopt};
    return {false, std::nullopt, after(now, left)};
}

void MeteoSidecars::after_processing(IngestContext& ctx, const fs::path& sidecar, SteadyTime now) {
    ready_.erase(sidecar);
    std::error_code ec;
    if (fs::exists(fs::symlink_status(sidecar, ec))) take(ctx, sidecar, now);
}

void MeteoSidecars::quarantine_orphans(IngestContext& ctx, SteadyTime now) {
    std::vector<fs::path> due;
    for (const auto& [path, at] : ready_) {
        if (at <= now) due.push_back(path);
    }
    for (const auto& p : due) settle(ctx, p, now, true);
}

std::optional<SteadyTime> MeteoSidecars::next_orphan_check() const {
    std::optional<SteadyTime> next;
    for (const auto& [path, at] : ready_) {
        if (!next || at < *next) next = at;
    }
    return next;
}

}  // namespace tlsmon
