#include "report/analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::report {

using registration::euler_from_rotation;

namespace {

const TruthEpoch* truth_at(const std::vector<TruthEpoch>& truth, std::int64_t time) {
    for (const TruthEpoch& t : truth) {
        if (t.time_unix == time) return &t;
    }
    return nullptr;
}

// The transformation the registration stored: 4x4 row-major, column-vector form, epoch's
// frame -> reference frame (docs/schema.md, registrations.transform).
Eigen::Affine3d stored_transform(const RegistrationRow& r) {
    Eigen::Matrix4d m;
    for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = r.transform[static_cast<std::size_t>(i)];
    return Eigen::Affine3d(m);
}

// What a zone quantity is scored against: the M3C2 and patch-based M3C2 distances along the
// zone's normal (median / mean), the keypoints along the surface against the mean true vector in
// the wall's directions (docs/keypoints.md: h = up × n, v = n × h, n the face's normal towards the
// scanner).
std::optional<std::string> truth_kind(const std::string& quantity) {
    if (quantity == "m3c2_median_m" || quantity == "pbm3c2_median_m")
        return "median of the true change along the normal";
    if (quantity == "m3c2_mean_m" || quantity == "pbm3c2_mean_m")
        return "mean of the true change along the normal";
    // The thermal compensation's (docs/thermal.md): the field's thermal part, and the rest.
    if (quantity == "m3c2_median_thermal_m" || quantity == "pbm3c2_median_thermal_m")
        return "median of the true thermal change along the normal";
    if (quantity == "m3c2_median_compensated_m" || quantity == "pbm3c2_median_compensated_m")
        return "median of the true change along the normal less its thermal part";
    if (quantity == "keypoint_along_surface_h_m") return "mean true change along the wall, h";
    if (quantity == "keypoint_along_surface_v_m") return "mean true change along the wall, v";
    return std::nullopt;
}

double truth_value(const std::string& quantity, const ZoneTruth& z, const ZoneFace& face) {
    if (quantity == "m3c2_median_m" || quantity == "pbm3c2_median_m") return z.normal_median;
    if (quantity == "m3c2_mean_m" || quantity == "pbm3c2_mean_m") return z.normal_mean;
    if (quantity == "m3c2_median_thermal_m" || quantity == "pbm3c2_median_thermal_m")
        return z.thermal_normal_median;
    if (quantity == "m3c2_median_compensated_m" || quantity == "pbm3c2_median_compensated_m")
        return z.normal_median - z.thermal_normal_median;
    const Eigen::Vector3d h = Eigen::Vector3d::UnitZ().cross(face.normal).normalized();
    if (quantity == "keypoint_along_surface_h_m") return z.mean_vector.dot(h);
    return z.mean_vector.dot(face.normal.cross(h));
}

}  // namespace

ErrorSummary summarise(const std::vector<double>& errors) {
    ErrorSummary s;
    s.n = errors.size();
    if (errors.empty()) return s;
    double sum = 0, sum2 = 0;
    for (const double e : errors) {
        sum += e;
        sum2 += e * e;
        s.max_abs = std::max(s.max_abs, std::abs(e));
    }
    s.bias = sum / static_cast<double>(s.n);
    s.rms = std::sqrt(sum2 / static_cast<double>(s.n));
    return s;
}

RunReport analyse(const RunData& run, const std::vector<TruthEpoch>& truth,
                  const std::filesystem::path& truth_folder) {
    RunReport out;
    out.database = run.database;
    out.scored = !truth.empty();
    out.reference = run.reference;
    out.truth_folder = truth_folder;
    out.truth_epochs = static_cast<int>(truth.size());
    out.campaigns = run.campaigns;
    for (const TruthEpoch& t : truth) {
        if (t.knocked && !out.knocked) out.knocked = t.knocked;
        if (t.step && !out.step) out.step = t.step;
    }

    // The reference epoch and its truth: every comparison is a difference to it (epoch 0 of
    // the simulator is not undeformed, nor is its scanner pose exact).
    const TruthEpoch* reference = nullptr;
    for (const RunEpoch& e : run.epochs) {
        if (run.reference && e.epoch.id == *run.reference) {
            reference = truth_at(truth, e.epoch.acquired);
        }
    }
    if (reference) out.reference_truth_epoch = reference->epoch;

    // ---- Registration ----
    std::vector<double> top_lengths, max_lengths;
    Eigen::Vector3d bias_sum = Eigen::Vector3d::Zero();
    for (const RunEpoch& e : run.epochs) {
        RegistrationCheck c;
        c.id = e.epoch.id;
        c.acquired = e.epoch.acquired;
        c.status = std::string(to_string(e.epoch.status));
        c.is_reference = run.reference && e.epoch.id == *run.reference;
        c.reason = e.epoch.reason;
        switch (e.epoch.status) {
            case EpochStatus::done:
                ++out.epochs_done;
                break;
            case EpochStatus::rejected:
                ++out.epochs_rejected;
                break;
            case EpochStatus::failed:
                ++out.epochs_failed;
                break;
            default:
                ++out.epochs_pending;
                break;
        }
        const TruthEpoch* t = truth_at(truth, e.epoch.acquired);
        if (t) c.truth_epoch = t->epoch;
        for (const TargetObservation& o : e.targets) {
            if (o.status == "found" || o.status == "excluded") {
                c.target_residuals.emplace_back(
                    o.target, std::hypot(o.residual[0], o.residual[1], o.residual[2]));
            }
            if (o.use == "excluded_outlier" || o.status == "excluded") {
                c.excluded.push_back(o.target);
                if (std::find(out.excluded_targets.begin(), out.excluded_targets.end(), o.target) ==
                    out.excluded_targets.end()) {
                    out.excluded_targets.push_back(o.target);
                }
                if (out.knocked && o.target == out.knocked->target && t &&
                    !out.knocked_excluded_from) {
                    out.knocked_excluded_from = t->epoch;
                }
            }
        }
        for (const RegistrationZoneSigma& z : e.zone_sigmas) {
            c.zone_sigma_m = std::max(c.zone_sigma_m.value_or(0.0), z.max_sigma_3d_m);
        }
        if (e.registration) {
            const RegistrationRow& r = *e.registration;
            c.registered = r.parameters.has_value();
            c.method = r.method;
            c.accepted = r.accepted;
            c.targets_used = r.target_count;
            c.target_rms_m = r.rms_m;
            if (!r.reason.empty() && c.reason.empty()) c.reason = r.reason;
            // e = T·q − H₀⁻¹·Hᵢ·q at q = Hᵢ⁻¹·p, where the epoch's scan sees the pier point p.
            if (c.registered && t && t->header_to_true && reference && reference->header_to_true) {
                const Eigen::Affine3d T = stored_transform(r);
                const Eigen::Affine3d exact =
                    reference->header_to_true->inverse() * *t->header_to_true;
                double worst = 0;
                for (const TruthSample& s : t->samples) {
                    const Eigen::Vector3d q = t->header_to_true->inverse() * s.point;
                    const Eigen::Vector3d err = T * q - exact * q;
                    worst = std::max(worst, err.norm());
                    if (s.name == "top_centre") c.top_error = err;
                }
                c.max_error = worst;
                if (r.parameters && r.sigmas) {
                    const Eigen::Vector3d angles = euler_from_rotation(exact.linear());
                    const Eigen::Vector3d t = exact.translation();
                    const std::array<double, 6> truth{angles.x(), angles.y(), angles.z(),
                                                      t.x(),      t.y(),      t.z()};
                    std::array<double, 6> error{};
                    for (std::size_t k = 0; k < 6; ++k) {
                        error[k] = (*r.parameters)[k] - truth[k];
                        // angles: the difference wrapped into (−π, π]
                        if (k < 3) error[k] = std::remainder(error[k], 2 * std::numbers::pi);
                    }
                    c.parameter_error = error;
                    c.parameter_sigma = r.sigmas;
                }
                if (c.accepted && !c.is_reference) {
                    max_lengths.push_back(worst);
                    if (c.top_error) {
                        top_lengths.push_back(c.top_error->norm());
                        bias_sum += *c.top_error;
                    }
                }
            }
        }
        out.registration.push_back(std::move(c));
        if (e.registration && e.registration->accepted && !e.registration->quality_json.empty()) {
            const auto q = nlohmann::json::parse(e.registration->quality_json, nullptr, false);
            for (const char* estimate : {"icp", "planes", "stable_areas"}) {
                if (!q.is_object() || !q.contains(estimate)) continue;
                const auto& chi2 = q[estimate].value("agreement_chi2", nlohmann::json());
                if (chi2.is_number()) {
                    out.chi_square_tests.push_back(
                        {e.epoch.id, std::string("agreement:") + estimate, chi2.get<double>(), 6});
                }
            }
        }
        // Each used target against the others' transformation, where at least four were
        // used (three: T_i has fewer than 3 degrees of freedom; its rank is not stored).
        const auto used = std::count_if(e.targets.begin(), e.targets.end(),
                                        [](const TargetObservation& o) { return o.use == "used"; });
        if (c.accepted && !c.is_reference && used >= 4) {
            for (const TargetObservation& o : e.targets) {
                if (o.use == "used" && o.statistic)
                    out.chi_square_tests.push_back(
                        {e.epoch.id, "no_change:targets", *o.statistic, 3});
            }
        }
    }
    out.registration_top_error = summarise(top_lengths);
    out.registration_max_error = summarise(max_lengths);
    if (!top_lengths.empty()) {
        const Eigen::Vector3d b = 1e3 * bias_sum / static_cast<double>(top_lengths.size());
        out.bias_vector_mm = {b.x(), b.y(), b.z()};
    }

    // ---- Zones ----
    for (const RunZone& z : run.zones) {
        ZoneCheck zc;
        zc.id = z.id;
        zc.zone = z.name;
        zc.no_change = z.no_change;
        if (z.box && out.scored) zc.face = zone_face(truth.front().pier, *z.box);
        if (zc.face && reference) {
            for (const TruthEpoch& t : truth) {
                if (t.missing) continue;
                zc.truth.emplace_back(t.epoch, zone_truth(*reference, t, *zc.face));
            }
            if (out.step) {
                const bool overlaps =
                    out.step->z_max >= zc.face->z_min && out.step->z_min <= zc.face->z_max;
                zc.step_zone =
                    overlaps && std::abs(out.step->displacement.dot(zc.face->normal)) > 0;
            }
        }
        for (const auto& [quantity, points] : z.series) {
            ZoneQuantityCheck q;
            q.zone = z.name;
            q.quantity = quantity;
            const auto kind = truth_kind(quantity);
            q.displacement = kind.has_value();
            if (kind && zc.face && reference) q.truth_kind = *kind;
            if (kind && z.no_change) q.truth_kind = "zero (a check zone, known not to move)";
            std::vector<double> errors;
            for (const SeriesPoint& p : points) {
                ZoneQuantityCheck::Row row;
                row.id = p.epoch;
                row.acquired = p.acquired;
                row.value = p.value;
                row.lod = p.uncertainty;
                row.significant = p.significant;
                const TruthEpoch* t = truth_at(truth, p.acquired);
                if (t) row.truth_epoch = t->epoch;
                if (kind && z.no_change) {
                    row.truth = 0.0;
                    if (std::isfinite(p.value)) errors.push_back(p.value);
                } else if (t && !q.truth_kind.empty()) {
                    row.truth =
                        truth_value(quantity, zone_truth(*reference, *t, *zc.face), *zc.face);
                    if (std::isfinite(p.value)) errors.push_back(p.value - *row.truth);
                }
                q.rows.push_back(row);
            }
            q.error = summarise(errors);
            zc.quantities.push_back(std::move(q));
        }
        out.zones.push_back(std::move(zc));
    }

    // ---- Alarms ----
    std::map<EpochId, int> truth_epoch_of;
    for (const RegistrationCheck& c : out.registration) {
        truth_epoch_of[c.id] = c.truth_epoch;
        if (c.truth_epoch >= 0) out.epoch_id[c.truth_epoch] = c.id;
    }
    for (const AlarmRule& rule : run.rules) {
        AlarmCheck a;
        a.id = rule.id;
        a.rule = rule.name;
        a.zone = rule.zone;
        a.quantity = rule.quantity;
        for (const ZoneCheck& zc : out.zones) {
            if (zc.zone != rule.zone) continue;
            a.step_zone = zc.step_zone;
            for (const ZoneQuantityCheck& q : zc.quantities) {
                if (q.quantity == rule.quantity && !q.rows.empty()) a.evaluated = true;
            }
        }
        if (out.step && a.step_zone) a.step_epoch = out.step->since_epoch;
        for (const AlarmEvent& ev : run.alarm_events) {
            if (ev.rule != rule.name) continue;
            const int te =
                ev.epoch && truth_epoch_of.count(*ev.epoch) ? truth_epoch_of[*ev.epoch] : -1;
            a.events.push_back(fmt::format(
                "{}: {} {}{}",
                ev.epoch ? fmt::format("epoch {}", *ev.epoch) : std::string("operator"), ev.kind,
                ev.level,
                ev.value ? fmt::format(" ({:+.2f} mm)", 1e3 * *ev.value) : std::string()));
            if (ev.kind != "raise") continue;
            ++a.raises;
            if (!out.scored) continue;
            if (a.step_epoch && te >= *a.step_epoch) {
                if (!a.first_raise_epoch) {
                    a.first_raise_epoch = te;
                    a.latency_epochs = te - *a.step_epoch;
                }
            } else {
                ++a.false_alarms;
            }
        }
        out.alarms.push_back(std::move(a));
    }
    return out;
}

}  // namespace tlsmon::report
