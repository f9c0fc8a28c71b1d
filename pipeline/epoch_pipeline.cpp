#include "pipeline/epoch_pipeline.hpp"

#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <cerrno>
#include <chrono>

#include "pipeline/epoch_files.hpp"
#include "pipeline/sha256.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool names_reference(const PipelineConfig& config, const Epoch& e) {
    const std::string& want = config.reference_epoch;
    if (want.empty()) return true;
    return want == e.sha256 || want == fs::path(e.file_path).filename().string();
}

// Size and mtime of a file, to see whether it changed while it was read.
std::pair<std::int64_t, std::int64_t> size_and_mtime(const fs::path& file) {
    struct stat st {};
    if (::lstat(file.c_str(), &st) != 0) return {-1, -1};
    return {st.st_size, std::int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec};
}

// `quarantine`: move the file to quarantine. Not when the file holds another content than
// the epoch's: that content is another epoch, which ingest finds under this name.
EpochOutcome fail(PipelineContext& ctx, const Epoch& epoch, const std::string& reason,
                  bool quarantine = true) {
    const fs::path file(epoch.file_path);
    std::optional<std::string> moved_to;
    std::error_code ec;
    // Only a regular file is moved: a symbolic link put in its place is never followed,
    // nor moved.
    if (quarantine && fs::is_regular_file(fs::symlink_status(file, ec))) {
        const fs::path to = free_name(ctx.config.quarantine, file.filename().string(),
                                      epoch.sha256.substr(0, 12));
        write_reason_file(to, file.string(), reason);
        moved_to = to.string();
    }
    // The row first, then the move: after a stop in between, ingest finds the file again,
    // sees the failed epoch and finishes the move (ingest.cpp, handle_known).
    ctx.db.epochs().fail(epoch.id, reason, moved_to);
    std::string where = "left in place";
    if (moved_to) {
        try {
            move_file(file, *moved_to);
            where = "moved to " + *moved_to;
        } catch (const Error& e) {
            where = std::string("could not be moved: ") + e.what();
        }
    }
    ctx.events.record(ctx.db, "error", "epoch_failed",
                      "epoch " + std::to_string(epoch.id) + " failed: " + reason + " (" +
                          file.string() + " " + where + ")",
                      epoch.id);
    return EpochOutcome::failed;
}

}  // namespace

void ensure_reference(PipelineContext& ctx) {
    if (ctx.db.epochs().reference()) return;
    for (const auto& e : ctx.db.series().epochs_in_range({})) {  // by acquisition time
        if (e.status != EpochStatus::done || !names_reference(ctx.config, e)) continue;
        ctx.db.epochs().set_reference(e.id);
        ctx.events.record(
            ctx.db, "info", "reference_epoch",
            "epoch " + std::to_string(e.id) + " (" + e.file_path + ") is the reference epoch",
            e.id);
        return;
    }
}

EpochOutcome process_epoch(PipelineContext& ctx, const Epoch& epoch) {
    const auto t0 = std::chrono::steady_clock::now();
    try {
        if (!ctx.db.epochs().claim(epoch.id)) return EpochOutcome::skipped;
        const fs::path file(epoch.file_path);
        std::error_code ec;
        if (!fs::exists(fs::symlink_status(file, ec))) {
            return fail(ctx, epoch, "the file vanished before it was processed");
        }
        // The bytes parsed are the bytes hashed: a file replaced under the same name while
        // its epoch waited is another epoch, whose results must not go to this one.
        const auto before = size_and_mtime(file);
        const auto read_again = [&] {
            ctx.db.epochs().release(epoch.id);
            spdlog::warn("{}: changed while it was read; epoch {} is read again", file.string(),
                         epoch.id);
            return EpochOutcome::skipped;
        };
        EpochResults results;
        const auto t_read = std::chrono::steady_clock::now();
        std::string bytes;
        try {
            bytes = read_file_bytes(file);
        } catch (const FileAccessError& e) {
            if (e.error_number() == ENOENT) {
                return fail(ctx, epoch, "the file vanished before it was processed");
            }
            return fail(ctx, epoch, e.what());
        }
        if (sha256_text(bytes) != epoch.sha256) {
            if (size_and_mtime(file) != before) return read_again();  // still being written
            return fail(
                ctx, epoch,
                file.string() + ": the file was replaced by other content before it was read",
                false);
        }
        try {
            const std::vector<Scan> scans = parse_scans(bytes, file);
            results.timings.read_ms = ms_since(t_read);
            if (size_and_mtime(file) != before) {  // PLY/PCD are read from the file again
                return read_again();
            }
            std::int64_t points = 0;
            for (const auto& s : scans) points += static_cast<std::int64_t>(s.size());
            if (points == 0) return fail(ctx, epoch, file.string() + ": the file holds no points");
            results.point_count = points;
        } catch (const StorageError&) {
            throw;
        } catch (const std::exception& e) {
            if (size_and_mtime(file) != before) {  // the error may come from the change
                return read_again();
            }
            return fail(ctx, epoch, e.what());
        }
        // Registration and the analyses plug in here as they become available.
        std::optional<fs::path> archive_to;
        if (ctx.config.archive_mode == ArchiveMode::move) {
            archive_to = free_name(ctx.config.archive, file.filename().string(),
                                   epoch.sha256.substr(0, 12));
            results.archive_path = archive_to->string();
        }
        results.timings.total_ms = ms_since(t0);
        ctx.db.results().commit(epoch.id, results);
        spdlog::info("epoch {} done: {} points, read {:.0f} ms ({})", epoch.id,
                     *results.point_count, *results.timings.read_ms, file.string());
        if (archive_to) {
            try {
                move_file(file, *archive_to);
            } catch (const Error& e) {
                ctx.events.record(ctx.db, "warning", "archive_failed", e.what(), epoch.id);
            }
        }
        try {
            ensure_reference(ctx);
        } catch (const StorageError& e) {
            spdlog::warn("the reference epoch is not set yet: {}", e.what());
        }
        return EpochOutcome::done;
    } catch (const StorageError& e) {
        ctx.events.record(
            ctx.db, "error", e.disk_full() ? "disk_full" : "database_error",
            "epoch " + std::to_string(epoch.id) + " kept pending, will retry: " + e.what(),
            epoch.id);
        try {
            ctx.db.epochs().release(epoch.id);
        } catch (const StorageError&) {
            // Still `processing`: recover_interrupted() before the retry puts it back.
        }
        return EpochOutcome::retry_later;
    }
}

}  // namespace tlsmon
