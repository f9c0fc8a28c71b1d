// ResultsWriter::commit: everything one processed epoch produced, and its final status, in ONE
// transaction (DESIGN.md "SQLite"): a crash or an error leaves nothing of it stored and the
// epoch `processing`, which recover_interrupted() turns back into `pending`.
#include "storage/results_writer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"
#include "storage/site.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

namespace {

// Arrays are stored little-endian (docs/schema.md); the daemon runs on x86-64 and arm64.
static_assert(std::endian::native == std::endian::little,
              "core point arrays and transforms are stored as little-endian floats");

void check_results(Connection& c, EpochId id, const EpochResults& r) {
    const std::string epoch = "epoch " + std::to_string(id) + ": ";
    if (r.outcome != EpochStatus::done && r.outcome != EpochStatus::rejected) {
        throw_storage(c, epoch + "an epoch commit ends in done or rejected, not " +
                             std::string(to_string(r.outcome)));
    }
    if (r.outcome == EpochStatus::rejected) {
        if (r.reason.empty()) throw_storage(c, epoch + "a rejected epoch needs a reason");
        if (!r.zone_results.empty() || !r.core_point_arrays.empty() || !r.keypoint_models.empty() ||
            !r.thermal_models.empty() || !r.thermal_compensations.empty()) {
            throw_storage(c, epoch + "a rejected epoch has no analysis results");
        }
    }
    if (r.meteo) {
        const bool processed_with =
            r.meteo->outcome == MeteoOutcome::used || r.meteo->outcome == MeteoOutcome::rejected;
        if (!processed_with || r.meteo->epoch != id) {
            throw_storage(c, epoch +
                                 "the commit records the sidecar the epoch was processed "
                                 "with (used or rejected, of this epoch)");
        }
    }
}

void write_registration(Connection& c, EpochId id, const RegistrationRow& reg) {
    SQLite::Statement s(c.db,
                        "INSERT INTO registrations (epoch_id, method, transform, target_count,"
                        " rms_m, max_residual_m, sigma0, accepted, quality_json, status, reason,"
                        " omega_rad, phi_rad, kappa_rad, tx_m, ty_m, tz_m, qw, qx, qy, qz,"
                        " sigma_omega_rad, sigma_phi_rad, sigma_kappa_rad, sigma_tx_m,"
                        " sigma_ty_m, sigma_tz_m, variance_factor, redundancy)"
                        " VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    s.bind(1, id);
    s.bind(2, reg.method);
    s.bind(3, reg.transform.data(), static_cast<int>(sizeof(double) * reg.transform.size()));
    s.bind(4, static_cast<std::int64_t>(reg.target_count));
    s.bind(5, reg.rms_m);
    s.bind(6, reg.max_residual_m);
    bind_optional(s, 7, reg.sigma0);
    s.bind(8, reg.accepted ? 1 : 0);
    s.bind(9, reg.quality_json);
    s.bind(10, reg.status);
    s.bind(11, reg.reason);
    for (int k = 0; k < 6; ++k) {
        bind_optional(s, 12 + k,
                      reg.parameters ? std::optional<double>((*reg.parameters)[k]) : std::nullopt);
    }
    for (int k = 0; k < 4; ++k) {
        bind_optional(s, 18 + k,
                      reg.quaternion ? std::optional<double>((*reg.quaternion)[k]) : std::nullopt);
    }
    for (int k = 0; k < 6; ++k) {
        bind_optional(s, 22 + k,
                      reg.sigmas ? std::optional<double>((*reg.sigmas)[k]) : std::nullopt);
    }
    bind_optional(s, 28, reg.variance_factor);
    bind_optional(s, 29, reg.redundancy);
    s.exec();
}

void write_targets(Connection& c, EpochId id, const std::vector<TargetObservation>& targets) {
    if (targets.empty()) return;
    SQLite::Statement s(c.db,
                        "INSERT INTO target_observations (epoch_id, target, kind, measured_x,"
                        " measured_y, measured_z, residual_x, residual_y, residual_z, stable,"
                        " used, status, reason, use, sigma_x, sigma_y, sigma_z, statistic,"
                        " critical, minimal_detectable_bias_m)"
                        " VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    for (const auto& t : targets) {
        s.reset();
        s.bind(1, id);
        s.bind(2, t.target);
        s.bind(3, t.kind);
        for (int i = 0; i < 3; ++i) s.bind(4 + i, t.measured[i]);
        for (int i = 0; i < 3; ++i) s.bind(7 + i, t.residual[i]);
        s.bind(10, t.stable ? 1 : 0);
        s.bind(11, t.used ? 1 : 0);
        s.bind(12, t.status);
        s.bind(13, t.reason);
        s.bind(14, t.use);
        for (int k = 0; k < 3; ++k) {
            bind_optional(s, 15 + k, t.sigma ? std::optional<double>((*t.sigma)[k]) : std::nullopt);
        }
        bind_optional(s, 18, t.statistic);
        bind_optional(s, 19, t.critical);
        bind_optional(s, 20, t.minimal_detectable_bias_m);
        s.exec();
    }
}

void write_planes(Connection& c, EpochId id, const std::vector<PlaneRow>& planes) {
    if (planes.empty()) return;
    SQLite::Statement s(c.db,
                        "INSERT INTO plane_observations (epoch_id, plane, zone, role, normal_x,"
                        " normal_y, normal_z, centroid_x, centroid_y, centroid_z,"
                        " reference_points, epoch_points, tilt_u_rad, tilt_v_rad, shift_m,"
                        " sigma_tilt_u_rad, sigma_tilt_v_rad, sigma_shift_m, statistic, critical,"
                        " significant) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    for (const auto& p : planes) {
        s.reset();
        s.bind(1, id);
        s.bind(2, p.plane);
        bind_optional(s, 3, p.zone.empty() ? std::nullopt : std::optional<std::string>(p.zone));
        s.bind(4, p.role);
        for (int k = 0; k < 3; ++k) s.bind(5 + k, p.normal[k]);
        for (int k = 0; k < 3; ++k) s.bind(8 + k, p.centroid[k]);
        s.bind(11, p.reference_points);
        s.bind(12, p.epoch_points);
        for (int k = 0; k < 3; ++k) s.bind(13 + k, p.change[k]);
        for (int k = 0; k < 3; ++k) s.bind(16 + k, p.sigma[k]);
        s.bind(19, p.statistic);
        s.bind(20, p.critical);
        s.bind(21, p.significant ? 1 : 0);
        s.exec();
    }
}

// 0.01 mm units, little-endian int16; −32768 for none (NaN), saturated at ±327.67 mm.
std::vector<char> hundredths_of_mm(const std::vector<float>& metres) {
    std::vector<char> out;
    out.reserve(2 * metres.size());
    for (const float v : metres) {
        std::int16_t q = std::numeric_limits<std::int16_t>::min();
        if (!std::isnan(v))
            q = static_cast<std::int16_t>(std::clamp(std::lround(v * 1e5), -32767L, 32767L));
        const auto u = static_cast<std::uint16_t>(q);
        out.push_back(static_cast<char>(u & 0xFF));
        out.push_back(static_cast<char>(u >> 8));
    }
    return out;
}

void write_stable_areas(Connection& c, EpochId id, const std::optional<StableAreaMask>& mask) {
    if (!mask) return;
    const auto& m = *mask;
    const std::size_t n = m.states.size();
    if (m.changes.size() != n || m.lods.size() != n || m.supervoxels.size() != n) {
        throw StorageError("stable-area mask of epoch " + std::to_string(id) +
                           ": states, changes, LoDs and supervoxels differ in number");
    }
    SQLite::Statement known(c.db,
                            "SELECT count(*) FROM stable_area_supervoxels WHERE"
                            " reference_epoch_id = ? AND segmentation = ?");
    known.bind(1, m.reference_epoch);
    known.bind(2, m.segmentation);
    known.executeStep();
    if (known.getColumn(0).getInt64() == 0) {
        SQLite::Statement s(c.db,
                            "INSERT INTO stable_area_supervoxels (reference_epoch_id, segmentation,"
                            " supervoxel, centroid_x, centroid_y, centroid_z, normal_x, normal_y,"
                            " normal_z, voxels, roughness_m) VALUES (?,?,?,?,?,?,?,?,?,?,?)");
        for (std::size_t k = 0; k < n; ++k) {
            const auto& v = m.supervoxels[k];
            s.reset();
            s.bind(1, m.reference_epoch);
            s.bind(2, m.segmentation);
            s.bind(3, static_cast<std::int64_t>(k));
            for (int j = 0; j < 3; ++j) s.bind(4 + j, v.centroid[j]);
            for (int j = 0; j < 3; ++j) s.bind(7 + j, v.normal[j]);
            s.bind(10, v.voxels);
            s.bind(11, v.roughness_m);
            s.exec();
        }
    }
    SQLite::Statement s(c.db,
                        "INSERT INTO stable_area_masks (epoch_id, reference_epoch_id, segmentation,"
                        " supervoxels, stable, unstable, stable_share, states, changes, lods)"
                        " VALUES (?,?,?,?,?,?,?,?,?,?)");
    s.bind(1, id);
    s.bind(2, m.reference_epoch);
    s.bind(3, m.segmentation);
    s.bind(4, static_cast<std::int64_t>(n));
    s.bind(5, m.stable);
    s.bind(6, m.unstable);
    s.bind(7, m.stable_share);
    s.bind(8, m.states.data(), static_cast<int>(n));
    const auto changes = hundredths_of_mm(m.changes);
    const auto lods = hundredths_of_mm(m.lods);
    s.bind(9, changes.data(), static_cast<int>(changes.size()));
    s.bind(10, lods.data(), static_cast<int>(lods.size()));
    s.exec();
}

void write_exclusions(Connection& c, EpochId id, const std::vector<std::string>& targets) {
    if (targets.empty()) return;
    SQLite::Statement s(c.db, "INSERT INTO target_exclusions (target, epoch_id) VALUES (?,?)");
    for (const auto& t : targets) {
        s.reset();
        s.bind(1, t);
        s.bind(2, id);
        s.exec();
    }
}

void write_zone_sigmas(Connection& c, EpochId id,
                       const std::vector<RegistrationZoneSigma>& sigmas) {
    if (sigmas.empty()) return;
    SQLite::Statement s(c.db,
                        "INSERT INTO registration_zone_sigmas (epoch_id, zone, max_sigma_3d_m)"
                        " VALUES (?,?,?)");
    for (const auto& z : sigmas) {
        s.reset();
        s.bind(1, id);
        s.bind(2, z.zone);
        s.bind(3, z.max_sigma_3d_m);
        s.exec();
    }
}

void write_zone_results(Connection& c, EpochId id, const std::vector<ZoneResult>& results) {
    if (results.empty()) return;
    std::map<std::string, ZoneId> zone_ids;
    std::map<std::string, std::int64_t> quantity_ids;
    // The epoch's acquisition time is part of the series' key (0011_series_by_time.sql).
    SQLite::Statement when(c.db, "SELECT acquired FROM epochs WHERE id = ?");
    when.bind(1, id);
    if (!when.executeStep()) throw_storage(c, "epoch " + std::to_string(id) + " vanished");
    const std::int64_t acquired = when.getColumn(0).getInt64();
    SQLite::Statement s(c.db,
                        "INSERT INTO zone_results (zone_id, quantity_id, acquired, epoch_id,"
                        " value, uncertainty, n, significant) VALUES (?,?,?,?,?,?,?,?)");
    for (const auto& r : results) {
        auto zone = zone_ids.find(r.zone);
        if (zone == zone_ids.end()) {
            zone = zone_ids.emplace(r.zone, zone_id_by_name(c, r.zone)).first;
        }
        auto quantity = quantity_ids.find(r.quantity);
        if (quantity == quantity_ids.end()) {
            quantity = quantity_ids.emplace(r.quantity, quantity_id(c, r.quantity)).first;
        }
        s.reset();
        s.bind(1, zone->second);
        s.bind(2, quantity->second);
        s.bind(3, acquired);
        s.bind(4, id);
        s.bind(5, r.value);
        bind_optional(s, 6, r.uncertainty);
        s.bind(7, static_cast<std::int64_t>(r.n));
        s.bind(8, r.significant ? 1 : 0);
        s.exec();
    }
}

void write_core_point_arrays(Connection& c, EpochId id, const std::vector<CorePointArray>& arrays) {
    if (arrays.empty()) return;
    SQLite::Statement s(c.db,
                        "INSERT INTO core_point_arrays (epoch_id, quantity, count, data)"
                        " VALUES (?,?,?,?)");
    for (const auto& a : arrays) {
        s.reset();
        s.bind(1, id);
        s.bind(2, a.quantity);
        s.bind(3, static_cast<std::int64_t>(a.values.size()));
        // bindNoCopy: the vector outlives exec().
        s.bindNoCopy(4, a.values.data(), static_cast<int>(a.values.size() * sizeof(float)));
        s.exec();
    }
}

void write_stages(Connection& c, EpochId id, const std::vector<StageRun>& stages) {
    if (stages.empty()) return;
    SQLite::Statement s(c.db,
                        "INSERT INTO epoch_stages (epoch_id, position, stage, ms, rejected, note)"
                        " VALUES (?,?,?,?,?,?)");
    for (std::size_t k = 0; k < stages.size(); ++k) {
        s.reset();
        s.bind(1, id);
        s.bind(2, static_cast<std::int64_t>(k));
        s.bind(3, stages[k].stage);
        s.bind(4, stages[k].ms);
        s.bind(5, stages[k].rejected);
        s.bind(6, stages[k].note);
        s.exec();
    }
}

void write_status(Connection& c, EpochId id, const EpochResults& r) {
    SQLite::Statement s(c.db,
                        "UPDATE epochs SET status = ?, reason = ?, updated = ?, point_count = ?,"
                        " read_ms = ?, register_ms = ?, analyse_ms = ?, total_ms = ?,"
                        " archive_path = coalesce(?, archive_path)"
                        " WHERE id = ? AND status = 'processing'");
    s.bind(1, std::string(to_string(r.outcome)));
    s.bind(2, r.reason);
    s.bind(3, static_cast<std::int64_t>(now_utc()));
    bind_optional(s, 4, r.point_count);
    bind_optional(s, 5, r.timings.read_ms);
    bind_optional(s, 6, r.timings.register_ms);
    bind_optional(s, 7, r.timings.analyse_ms);
    bind_optional(s, 8, r.timings.total_ms);
    bind_optional(s, 9, r.archive_path);
    s.bind(10, id);
    if (s.exec() != 1) {
        throw_storage(c, "epoch " + std::to_string(id) +
                             " is not processing; claim it before committing its results");
    }
}

}  // namespace

void ResultsWriter::commit(EpochId id, const EpochResults& results) {
    commit(id, results, {});
}

void ResultsWriter::commit(EpochId id, const EpochResults& results,
                           const AlarmEvaluation& evaluate) {
    check_results(*c_, id, results);
    const std::string context = "committing epoch " + std::to_string(id);
    guarded(*c_, context.c_str(), [&] {
        // IMMEDIATE: take the write lock at BEGIN, so a busy database fails before any work.
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        // The status first: an epoch that is not ours fails before anything is written.
        write_status(*c_, id, results);
        write_stages(*c_, id, results.stages);
        if (results.registration) write_registration(*c_, id, *results.registration);
        write_targets(*c_, id, results.targets);
        write_exclusions(*c_, id, results.target_exclusions);
        write_zone_sigmas(*c_, id, results.registration_zone_sigmas);
        write_planes(*c_, id, results.planes);
        write_stable_areas(*c_, id, results.stable_areas);
        for (const auto& z : results.new_zones) Site(*c_).upsert_zone(z.name, z.definition_json);
        write_zone_results(*c_, id, results.zone_results);
        write_core_point_arrays(*c_, id, results.core_point_arrays);
        write_keypoint_models(*c_, id, results.keypoint_models);
        write_thermal_rows(*c_, id, results.thermal_models, results.thermal_compensations);
        for (const auto& a : results.alarm_states) write_alarm_state(*c_, a);
        for (const auto& e : results.alarm_events) write_alarm_event(*c_, e);
        if (evaluate) {
            const AlarmRows rows = evaluate(AlarmStore(*c_), SeriesReader(*c_));
            for (const auto& a : rows.states) write_alarm_state(*c_, a);
            for (const auto& e : rows.events) write_alarm_event(*c_, e);
            for (const auto& e : rows.system_events) write_system_event(*c_, e);
        }
        for (const auto& e : results.system_events) write_system_event(*c_, e);
        if (results.meteo) write_meteo_sidecar(*c_, *results.meteo);
        tx.commit();
    });
}

}  // namespace tlsmon
