#include "pipeline/epoch_pipeline.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <cerrno>
#include <chrono>

#include "core/utc_time.hpp"
#include "formats/meteo_csv.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/alarm_evaluation.hpp"
#include "pipeline/epoch_files.hpp"
#include "pipeline/sha256.hpp"
#include "pipeline/site_stages.hpp"

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

// The reference epoch's scans, read again from where its file is now (the archive, or the
// ingest folder with archive = "keep") and checked against its sha256.
ReferenceEpoch::Scans read_reference_scans(const Epoch& reference) {
    const fs::path file =
        reference.archive_path ? fs::path(*reference.archive_path) : fs::path(reference.file_path);
    HashedBytes content;
    try {
        content = read_file_hashed(file);
    } catch (const FileAccessError& e) {
        throw Error("the reference epoch's scan is needed and cannot be read: " +
                    std::string(e.what()));
    }
    if (content.sha256 != reference.sha256) {
        throw Error("the reference epoch's scan is needed, and " + file.string() +
                    " no longer holds its content (sha256 " + content.sha256.substr(0, 12) +
                    " instead of " + reference.sha256.substr(0, 12) + ")");
    }
    return std::make_shared<const std::vector<Scan>>(parse_scans(content.bytes, file));
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
        const fs::path to =
            free_name(ctx.config.quarantine, file.filename().string(), epoch.sha256.substr(0, 12));
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

namespace {

// The reference epoch for `epoch`: the one the database names, or `epoch` itself when none is
// set yet and it may be the reference (ensure_reference records it after the commit).
std::optional<ReferenceEpoch> reference_for(PipelineContext& ctx, const Epoch& epoch,
                                            const ReferenceEpoch::Scans& scans) {
    if (const auto id = ctx.db.epochs().reference()) {
        const auto reference = ctx.db.epochs().find(*id);
        if (!reference) return std::nullopt;
        return ReferenceEpoch(*reference, [reference] { return read_reference_scans(*reference); });
    }
    if (!names_reference(ctx.config, epoch)) return std::nullopt;
    return ReferenceEpoch(epoch, [scans] { return scans; });
}

// What the earlier epochs left for this one: the targets excluded as moved, the reference
// epoch's air, the stored series, the last accepted transformation.
StageHistory history_for(PipelineContext& ctx, const ReferenceEpoch& reference,
                         const Epoch& epoch) {
    StageHistory history;
    history.excluded_targets = ctx.db.registrations().excluded_targets();
    history.outlier_runs =
        ctx.db.registrations().outlier_runs(epoch.acquired, kMaxConfirmExclusionEpochs);
    for (const auto& m : ctx.db.meteo().of_epoch(reference.epoch().id)) {
        if (m.outcome == MeteoOutcome::used && m.values) history.reference_meteo = m;
    }
    history.series = &ctx.db.series();
    history.thermal = &ctx.db.thermal();
    if (const auto m = ctx.db.registrations().last_accepted_transform(epoch.acquired)) {
        registration::RigidTransform t;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) t.rotation(r, c) = (*m)[4 * r + c];
            t.translation(r) = (*m)[4 * r + 3];
        }
        history.last_transform = t;
    }
    history.stable_area_states = [&db = ctx.db, acquired = epoch.acquired,
                                  reference = reference.epoch().id](const std::string& segmentation,
                                                                    int count) {
        return db.registrations().recent_stable_area_states(acquired, reference, segmentation,
                                                            count);
    };
    return history;
}

// One stage, timed and listed in the epoch's stages; an Error of the stage (e.g. the
// reference's file is gone and a product is not cached) rejects the epoch with its reason.
StageVerdict run_timed(const Stage& stage, StageContext& sc) {
    const auto t0 = std::chrono::steady_clock::now();
    StageVerdict verdict;
    try {
        verdict = stage.run(sc);
    } catch (const StorageError&) {
        throw;
    } catch (const Error& e) {
        verdict.rejected = std::string(stage.name()) + ": " + e.what();
    }
    sc.results.stages.push_back(
        StageRun{stage.name(), ms_since(t0), verdict.rejected, verdict.note});
    return verdict;
}

// The epoch through the stages (the data flow of docs/pipeline.md); the first that cannot
// analyse it rejects it.
StageVerdict run_stages(PipelineContext& ctx, const EpochInput& input, EpochResults& results) {
    // 1. Epoch 0 of every analysis.
    std::optional<ReferenceEpoch> reference = reference_for(ctx, input.epoch, input.scans);
    if (!reference) {
        return StageVerdict{"no reference epoch yet: ingest.reference_epoch = '" +
                                ctx.config.reference_epoch + "' has not been processed",
                            ""};
    }
    // 2. What the stages may read of the epochs before.
    const StageHistory history = history_for(ctx, *reference, input.epoch);
    // 3. Coverage, registration, M3C2, keypoints (site_stages): each prepares its reference
    //    product (cached) and measures the epoch into its own rows.
    StageOutputs outputs;
    StageContext sc{input, *reference, ctx.cache, history, ctx.config.zones, outputs, results};
    const StageList stages =
        ctx.config.stages.empty() ? site_stages(ctx.config) : ctx.config.stages;
    for (const auto& stage : stages) {
        if (auto verdict = run_timed(*stage, sc); !verdict.ran()) return verdict;
    }
    return {};
}

}  // namespace

namespace {

// The sidecar as the epoch uses it (read before the stages), and where it goes after the
// commit: beside the scan in the archive when used, to quarantine with its reason when
// rejected. No sidecar: said in the commit when the scan waited for one.
std::optional<MeteoSidecar> read_meteo(PipelineContext& ctx, const Epoch& epoch,
                                       const std::optional<fs::path>& sidecar) {
    if (!sidecar) return std::nullopt;
    return read_epoch_meteo(*sidecar, epoch, ctx.config.meteo);
}

void place_meteo(PipelineContext& ctx, const Epoch& epoch, const fs::path& sidecar,
                 const std::optional<fs::path>& scan_archived, MeteoSidecar& meteo,
                 EpochResults& results) {
    const std::string tag = meteo.sha256.substr(0, 12);
    if (meteo.outcome == MeteoOutcome::used) {
        if (scan_archived) {
            const std::string name = scan_archived->stem().string() + ".meteo.csv";
            meteo.path = free_name(scan_archived->parent_path(), name, tag).string();
        }
        spdlog::info("epoch {}: meteo from {} line {} ({}): {} °C, {} hPa, {} %", epoch.id,
                     sidecar.string(), meteo.values->line, format_utc(meteo.values->time),
                     meteo.values->air_temperature_c, meteo.values->pressure_hpa,
                     meteo.values->relative_humidity_pct);
    } else {
        const fs::path to = free_name(ctx.config.quarantine, meteo.file_name, tag);
        write_reason_file(to, sidecar.string(), meteo.reason);
        meteo.path = to.string();
        const std::string what = "epoch " + std::to_string(epoch.id) +
                                 ": meteo sidecar rejected: " + meteo.reason + "; moved to " +
                                 to.string() + ", the epoch is processed without meteo";
        spdlog::warn("{}", what);
        results.system_events.push_back(
            SystemEvent{now_utc(), "warning", "meteo_rejected", what, epoch.id});
    }
}

void say_no_meteo(PipelineContext& ctx, const Epoch& epoch, EpochResults& results) {
    const fs::path expected = meteo_sidecar_of(epoch.file_path);
    if (ctx.config.meteo.wait_seconds <= 0) {
        spdlog::info("epoch {}: no meteo sidecar {}; processed without meteo", epoch.id,
                     expected.string());
        return;
    }
    const std::string what =
        "epoch " + std::to_string(epoch.id) + ": no meteo sidecar " + expected.string() +
        " within meteo.wait_seconds = " + fmt::format("{:g}", ctx.config.meteo.wait_seconds) +
        " s; processed without meteo";
    spdlog::warn("{}", what);
    results.system_events.push_back(
        SystemEvent{now_utc(), "warning", "meteo_missing", what, epoch.id});
}

}  // namespace

EpochOutcome process_epoch(PipelineContext& ctx, const Epoch& epoch, HashedBytes* preloaded,
                           const std::optional<fs::path>& sidecar) {
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
        const auto before = file_stamp(file);
        const auto read_again = [&] {
            ctx.db.epochs().release(epoch.id);
            spdlog::warn("{}: changed while it was read; epoch {} is read again", file.string(),
                         epoch.id);
            return EpochOutcome::skipped;
        };
        EpochResults results;
        const auto t_read = std::chrono::steady_clock::now();
        HashedBytes content;
        try {
            // Ingest just read and hashed this file: its bytes serve if the file is unchanged.
            if (preloaded && preloaded->sha256 == epoch.sha256 && preloaded->stamp == before) {
                content = std::move(*preloaded);
            } else {
                content = read_file_hashed(file);
            }
        } catch (const FileAccessError& e) {
            if (e.error_number() == ENOENT) {
                return fail(ctx, epoch, "the file vanished before it was processed");
            }
            return fail(ctx, epoch, e.what());
        }
        if (content.sha256 != epoch.sha256) {
            if (file_stamp(file) != before) return read_again();  // still being written
            return fail(
                ctx, epoch,
                file.string() + ": the file was replaced by other content before it was read",
                false);
        }
        std::shared_ptr<const std::vector<Scan>> scans;
        try {
            scans = std::make_shared<const std::vector<Scan>>(parse_scans(content.bytes, file));
            results.timings.read_ms = ms_since(t_read);
            std::int64_t points = 0;
            for (const auto& s : *scans) points += static_cast<std::int64_t>(s.size());
            if (points == 0) return fail(ctx, epoch, file.string() + ": the file holds no points");
            results.point_count = points;
        } catch (const StorageError&) {
            throw;
        } catch (const std::exception& e) {
            if (file_stamp(file) != before) {  // the error may come from the change
                return read_again();
            }
            return fail(ctx, epoch, e.what());
        }
        content = {};  // the scan is parsed; its bytes are not needed any more

        std::optional<MeteoSidecar> meteo = read_meteo(ctx, epoch, sidecar);
        EpochInput input{epoch, scans};
        if (meteo && meteo->outcome == MeteoOutcome::used) input.meteo = meteo;

        const auto t_analyse = std::chrono::steady_clock::now();
        const StageVerdict verdict = run_stages(ctx, input, results);
        results.timings.analyse_ms = ms_since(t_analyse);
        if (!verdict.ran()) {
            results.outcome = EpochStatus::rejected;
            results.reason = verdict.rejected;
            // A later stage's rejection voids the series an earlier one measured (the plane
            // series of an accepted registration); the registration's own rows stay.
            results.zone_results.clear();
            results.core_point_arrays.clear();
            results.keypoint_models.clear();
        }

        std::optional<fs::path> archive_to;
        if (ctx.config.archive_mode == ArchiveMode::move) {
            archive_to =
                free_name(ctx.config.archive, file.filename().string(), epoch.sha256.substr(0, 12));
            results.archive_path = archive_to->string();
        }
        if (meteo) {
            place_meteo(ctx, epoch, *sidecar, archive_to, *meteo, results);
            results.meteo = meteo;
        } else {
            say_no_meteo(ctx, epoch, results);
        }
        results.timings.total_ms = ms_since(t0);
        if (!verdict.ran()) {
            results.system_events.push_back(SystemEvent{
                now_utc(), "warning", "epoch_rejected",
                "epoch " + std::to_string(epoch.id) + " rejected: " + verdict.rejected, epoch.id});
        }
        // The alarm rules: the step after the stages, inside the commit, on the rows it writes
        // (alarm_evaluation.hpp).
        const auto evaluate_alarms = [&](const AlarmStore& alarms, const SeriesReader& series) {
            return evaluate_epoch_alarms(ctx.config.alarm_rules, epoch, results, alarms, series);
        };
        ctx.db.results().commit(epoch.id, results, evaluate_alarms);
        if (verdict.ran()) {
            spdlog::info("epoch {} done: {} points, read {:.0f} ms, analyses {:.0f} ms ({})",
                         epoch.id, *results.point_count, *results.timings.read_ms,
                         *results.timings.analyse_ms, file.string());
        } else {
            spdlog::warn("epoch {} rejected: {} ({})", epoch.id, verdict.rejected, file.string());
        }
        if (archive_to) {
            try {
                move_file(file, *archive_to);
            } catch (const Error& e) {
                ctx.events.record(ctx.db, "warning", "archive_failed", e.what(), epoch.id);
            }
        }
        // The sidecar after its scan: after a stop in between, the ingest finds it again,
        // knows it by its sha256 and finishes the move (daemon/ingest_meteo.cpp).
        if (meteo && meteo->path) {
            try {
                move_file(*sidecar, *meteo->path);
            } catch (const Error& e) {
                ctx.events.record(ctx.db, "warning", "archive_failed", e.what(), epoch.id);
            }
        }
        try {
            ensure_reference(ctx);
        } catch (const StorageError& e) {
            spdlog::warn("the reference epoch is not set yet: {}", e.what());
        }
        return verdict.ran() ? EpochOutcome::done : EpochOutcome::rejected;
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
