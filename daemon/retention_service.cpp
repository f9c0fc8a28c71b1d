#include "daemon/retention_service.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

#include "daemon/archive_pass.hpp"
#include "daemon/retention_pass.hpp"

namespace tlsmon {

RetentionService::RetentionService(const RetentionPolicy& maps, const ArchivePolicy& archive,
                                   std::filesystem::path archive_folder,
                                   std::filesystem::path database)
    : policy_(maps),
      archive_(archive),
      archive_folder_(std::move(archive_folder)),
      database_(std::move(database)),
      thread_([this] { run(); }) {}

RetentionService::~RetentionService() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

bool RetentionService::stopping() {
    std::lock_guard lock(mutex_);
    return stop_;
}

void RetentionService::thin_maps(EpochDatabase& db) {
    const auto r = run_retention_pass(db, policy_, [this] { return stopping(); });
    if (r.epochs_thinned > 0 || r.size_after != r.size_before) {
        spdlog::info(
            "retention: maps of {} epochs thinned ({:.1f} MiB of map data); database "
            "{:.1f} -> {:.1f} MiB{}",
            r.epochs_thinned, static_cast<double>(r.map_bytes_deleted) / 1048576.0,
            static_cast<double>(r.size_before) / 1048576.0,
            static_cast<double>(r.size_after) / 1048576.0, r.stopped ? " (interrupted)" : "");
    }
    if (!r.vacuum_error.empty()) {
        spdlog::warn("retention: the database was not shrunk: {}", r.vacuum_error);
    }
}

void RetentionService::thin_archive(EpochDatabase& db) {
    const auto r = run_archive_pass(db, archive_, archive_folder_, [this] { return stopping(); });
    if (r.scans_removed > 0 || r.scans_reencoded > 0 || r.deletions_finished > 0) {
        spdlog::info(
            "archive: {} scans removed, {} re-encoded as E57 ({:.1f} -> {:.1f} MiB); {:.1f} MiB "
            "freed; the archive held {} scans, {:.1f} MiB{}",
            r.scans_removed + r.deletions_finished, r.scans_reencoded,
            static_cast<double>(r.reencoded_bytes_before) / 1048576.0,
            static_cast<double>(r.reencoded_bytes_after) / 1048576.0,
            static_cast<double>(r.bytes_freed) / 1048576.0, r.plan.scans,
            static_cast<double>(r.plan.bytes) / 1048576.0, r.stopped ? " (interrupted)" : "");
    }
    for (const auto& e : r.errors) spdlog::warn("archive: {}", e);
}

void RetentionService::run() {
    const auto interval = std::chrono::duration<double>(policy_.interval);
    std::string last_error;  // logged once until it changes
    for (;;) {
        try {
            auto db = EpochDatabase::open(database_, EpochDatabase::Mode::read_write);
            if (policy_.enabled) thin_maps(db);
            if (archive_.enabled && !stopping()) thin_archive(db);
            last_error.clear();
        } catch (const std::exception& e) {
            // Busy, full or gone: nothing was half done (every step is one transaction); the
            // next pass starts over from a fresh plan.
            if (e.what() != last_error) spdlog::error("retention pass failed: {}", e.what());
            last_error = e.what();
        }
        std::unique_lock lock(mutex_);
        if (cv_.wait_for(lock, interval, [this] { return stop_; })) return;
    }
}

}  // namespace tlsmon
