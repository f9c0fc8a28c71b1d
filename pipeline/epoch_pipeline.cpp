#include "pipeline/epoch_pipeline.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cmath>

#include "core/utc_time.hpp"
#include "formats/meteo_csv.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/alarm_evaluation.hpp"
#include "pipeline/epoch_files.hpp"
#include "pipeline/icp_registration.hpp"
#include "pipeline/sha256.hpp"

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

// What the registration stage measured, as the commit stores it.
void record_registration(const RegistrationResult& r, const StageVerdict& verdict, EpochId epoch,
                         EpochResults& results) {
    namespace reg = registration;
    RegistrationRow row;
    row.method = registration_method(r);
    row.quality_json = fmt::format(
        R"({{"atmosphere":"{}","epoch_ppm":{},"reference_ppm":{}{}}})",
        r.epoch_range_scale ? "corrected" : "not_corrected",
        r.epoch_range_scale ? fmt::format("{:.3f}", (*r.epoch_range_scale - 1) * 1e6) : "null",
        r.reference_range_scale ? fmt::format("{:.3f}", (*r.reference_range_scale - 1) * 1e6)
                                : "null",
        icp_quality_json(r));
    row.status = name_of(r.tested.status);
    // Accepted with a scaled covariance: the reason says by how much, and why.
    row.reason = verdict.rejected.empty() &&
                         r.tested.status == registration::RegistrationStatus::accepted_scaled
                     ? r.tested.reason
                     : verdict.rejected;
    row.target_count = r.used;
    row.rms_m = r.rms;
    row.max_residual_m = r.max_residual;
    row.accepted = r.accepted();
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    if (const auto& T = r.tested.transform) {
        M = T->matrix();
        row.sigma0 = std::sqrt(T->variance_factor);
        row.variance_factor = T->variance_factor;
        row.redundancy = T->redundancy;
        row.parameters = std::array<double, 6>{
            T->omega, T->phi, T->kappa, T->translation.x(), T->translation.y(), T->translation.z()};
        const auto s = T->sigmas();
        row.sigmas = std::array<double, 6>{s(0), s(1), s(2), s(3), s(4), s(5)};
        row.quaternion = std::array<double, 4>{T->quaternion.w(), T->quaternion.x(),
                                               T->quaternion.y(), T->quaternion.z()};
    }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) row.transform[4 * i + j] = M(i, j);
    results.registration = row;
    for (std::size_t i = 0; i < r.measured.size(); ++i) {
        const auto& m = r.measured[i];
        TargetObservation o;
        o.target = m.name;
        o.kind = to_string(m.kind);
        o.status = m.status;
        o.reason = m.reason;
        for (int k = 0; k < 3; ++k)
            o.measured[k] = m.found() || m.status == "excluded" ? m.centre[k] : 0.0;
        if (m.found() || m.status == "excluded") {
            const Eigen::Vector3d s = m.covariance.diagonal().cwiseSqrt();
            o.sigma = std::array<double, 3>{s.x(), s.y(), s.z()};
        }
        if (i < r.tested.targets.size()) {
            const auto& v = r.tested.targets[i];
            o.use = name_of(v.use);
            o.used = v.use == reg::TargetUse::used;
            o.stable =
                v.use != reg::TargetUse::excluded_outlier && v.use != reg::TargetUse::suspect;
            for (int k = 0; k < 3; ++k)
                o.residual[k] = std::isfinite(v.residual[k]) ? v.residual[k] : 0.0;
            if (v.statistic > 0 || v.critical > 0) {
                o.statistic = v.statistic;
                o.critical = v.critical;
            }
            if (std::isfinite(v.minimal_detectable_bias)) {
                o.minimal_detectable_bias_m = v.minimal_detectable_bias;
            }
        } else {
            o.used = false;
        }
        results.targets.push_back(std::move(o));
    }
    results.target_exclusions = r.newly_excluded;
    for (const auto& name : r.newly_excluded) {
        results.system_events.push_back(
            SystemEvent{now_utc(), "warning", "target_excluded",
                        "target " + name +
                            " moved and is excluded from the registration until it is "
                            "re-surveyed",
                        epoch});
    }
    if (r.accepted()) {
        for (const auto& z : r.zones) {
            results.registration_zone_sigmas.push_back({z.zone, z.max_sigma_3d});
        }
    }
}

// The row of an epoch that no registration could take to the reference's frame: the
// reference itself is its own datum (identity, accepted); any other epoch stays in the
// scanner's frame, `unregistered`, and its values raise no alarm (docs/registration.md).
RegistrationRow datum_without_registration(bool is_reference) {
    RegistrationRow row;
    const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) row.transform[4 * i + j] = I(i, j);
    if (is_reference) {
        row.method = "reference";
        row.status = "reference";
        row.accepted = true;
        row.reason = "the reference epoch: its own frame is the datum";
    } else {
        row.method = kUnregistered;
        row.status = kUnregistered;
        row.accepted = false;
        row.reason =
            "not registered: no [[target]] and no ICP fallback on [[stable_region]]s are "
            "configured; the epoch stays in the scanner's frame, its values raise no alarm";
    }
    return row;
}

// The stages in order. Each gets the epoch, the reference and its own config section, and
// records its time; the first that cannot run for this epoch decides its rejection.
StageVerdict run_stages(PipelineContext& ctx, const EpochInput& input, EpochResults& results) {
    std::optional<ReferenceEpoch> reference = reference_for(ctx, input.epoch, input.scans);
    if (!reference) {
        StageVerdict none;
        none.rejected = "no reference epoch yet: ingest.reference_epoch = '" +
                        ctx.config.reference_epoch + "' has not been processed";
        return none;
    }
    const auto timed = [&](const char* stage, auto&& run) {
        const auto t0 = std::chrono::steady_clock::now();
        StageVerdict verdict;
        try {
            verdict = run();
        } catch (const StorageError&) {
            throw;
        } catch (const Error& e) {  // e.g. the reference's file is gone and a product is not cached
            verdict.rejected = std::string(stage) + ": " + e.what();
        }
        results.stages.push_back(StageRun{stage, ms_since(t0), verdict.rejected, verdict.note});
        return verdict;
    };

    CoverageResult coverage;
    if (auto v = timed("coverage",
                       [&] {
                           return check_coverage(ctx.config.coverage, input, *reference, ctx.cache,
                                                 coverage);
                       });
        !v.ran()) {
        return v;
    }
    StageOutputs outputs;
    const bool is_reference = reference->epoch().id == input.epoch.id;
    if (!can_register(ctx.config.registration) ||
        (is_reference && ctx.config.registration.targets.empty())) {
        // Every epoch states its datum: the reference's own frame (never an ICP of the
        // reference onto itself, which a sampled surface need not return as the identity),
        // or none at all.
        results.registration = datum_without_registration(is_reference);
        results.stages.push_back(StageRun{"registration", 0.0, "", results.registration->reason});
    } else {
        RegistrationResult registration;
        const auto excluded = ctx.db.registrations().excluded_targets();
        // The reference epoch's own air: its stored meteo (this epoch's when it is the
        // reference itself).
        std::optional<MeteoSidecar> reference_meteo;
        if (reference->epoch().id == input.epoch.id) {
            reference_meteo = input.meteo;
        } else {
            for (const auto& m : ctx.db.meteo().of_epoch(reference->epoch().id)) {
                if (m.outcome == MeteoOutcome::used && m.values) reference_meteo = m;
            }
        }
        bool measured = false;
        auto v = timed("registration", [&] {
            const auto verdict =
                register_to_reference(ctx.config.registration, input, *reference, ctx.cache,
                                      excluded, reference_meteo, registration);
            measured = true;
            return verdict;
        });
        if (measured) record_registration(registration, v, input.epoch.id, results);
        if (!v.ran()) return v;
        outputs.to_reference = registration.tested.transform;
        if (registration.epoch_range_scale && !input.scans->empty()) {
            outputs.range_scale = *registration.epoch_range_scale;
            outputs.scanner = input.scans->front().scanner_position();
            outputs.reference_range_scale = registration.reference_range_scale.value_or(1.0);
        }
    }
    if (ctx.config.m3c2.enabled && !ctx.config.m3c2.zones.empty()) {
        if (auto v = timed("m3c2",
                           [&] {
                               return run_m3c2(ctx.config.m3c2, input, *reference, ctx.cache,
                                               outputs, results);
                           });
            !v.ran()) {
            return v;
        }
    }
    const KeypointConfig& kp = ctx.config.keypoints;
    if (kp.enabled && (kp.segments == KeypointSegments::bands || !kp.zones.empty())) {
        std::vector<std::pair<std::string, std::string>> band_zones;
        if (auto v = timed("keypoints",
                           [&] {
                               return run_keypoints(kp, input, *reference, ctx.cache, outputs,
                                                    ctx.db.series(), band_zones, results);
                           });
            !v.ran()) {
            return v;
        }
        // The rows' band zones must exist before the commit (idempotent).
        for (const auto& [name, definition] : band_zones)
            ctx.db.site().upsert_zone(name, definition);
    }
    // Zones and alarms follow here, in this order, with `outputs`.
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
        // The alarm rules run inside the commit, on the rows it writes (alarm_evaluation.hpp).
        ctx.db.results().commit(epoch.id, results,
                                [&](const AlarmStore& alarms, const SeriesReader& series) {
                                    return evaluate_epoch_alarms(ctx.config.alarm_rules, epoch,
                                                                 results, alarms, series);
                                });
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
