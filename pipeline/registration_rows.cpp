#include "pipeline/registration_rows.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/utc_time.hpp"
#include "pipeline/icp_registration.hpp"
#include "pipeline/registration_on_planes.hpp"
#include "pipeline/stable_area_registration.hpp"

namespace tlsmon {

void record_registration(const RegistrationResult& r, const StageVerdict& verdict, EpochId epoch,
                         EpochResults& results) {
    namespace reg = registration;
    RegistrationRow row;
    row.method = registration_method(r);
    const auto ppm = [](const std::optional<double>& scale) {
        return scale ? nlohmann::json((*scale - 1) * 1e6) : nlohmann::json(nullptr);
    };
    nlohmann::json quality{{"atmosphere", r.epoch_range_scale ? "corrected" : "not_corrected"},
                           {"epoch_ppm", ppm(r.epoch_range_scale)},
                           {"reference_ppm", ppm(r.reference_range_scale)}};
    if (r.icp) quality["icp"] = icp_quality(*r.icp);
    if (r.planes) quality["planes"] = plane_quality(*r.planes);
    if (r.stable_areas) quality["stable_areas"] = stable_area_quality(*r.stable_areas);
    if (const auto& m = r.stable_areas; m && m->patches.size() == m->states.size()) {
        StableAreaMask mask;
        mask.reference_epoch = m->reference_epoch;
        mask.segmentation = m->segmentation;
        for (const auto& p : m->patches) {
            mask.supervoxels.push_back({{p.centroid.x(), p.centroid.y(), p.centroid.z()},
                                        {p.normal.x(), p.normal.y(), p.normal.z()},
                                        static_cast<std::int64_t>(p.samples),
                                        p.sigma});
        }
        for (const auto st : m->states) mask.states.push_back(static_cast<std::uint8_t>(st));
        mask.changes = m->changes;
        mask.lods = m->lods;
        mask.stable = static_cast<std::int64_t>(m->stable);
        mask.unstable = static_cast<std::int64_t>(m->unstable);
        mask.stable_share = m->stable_share;
        results.stable_areas = std::move(mask);
    }
    row.quality_json = quality.dump();
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
    for (const auto& name : r.outliers) {
        results.system_events.push_back(SystemEvent{
            now_utc(), "warning", "target_outlier",
            "target " + name +
                " failed its outlier test and is left out of this epoch's registration; it is "
                "excluded as moved once it fails in registration.confirm_exclusion_epochs "
                "consecutive epochs",
            epoch});
    }
    if (!r.accepted()) return;
    // A station change found by the planes or, refused from the last pose, by the stable areas.
    std::optional<StationChange> change;
    if (r.planes && r.planes->used) change = r.planes->station_change;
    if (!change && r.stable_areas && r.stable_areas->used) change = r.stable_areas->station_change;
    if (change) {
        results.system_events.push_back(SystemEvent{
            now_utc(), "warning", "station_change",
            describe(*change) +
                "; the reference is unchanged, every later epoch is registered from this pose",
            epoch});
    }
    if (r.stable_areas) {
        for (const auto& a : r.stable_areas->new_unstable_areas) {
            results.system_events.push_back(SystemEvent{
                now_utc(), "warning", "unstable_area",
                fmt::format("unstable area outside the zones: {} supervoxels about ({:.1f}, "
                            "{:.1f}, {:.1f}) m, {:.1f} m across, unstable in {} epochs in a row; "
                            "change {:+.2f} to {:+.2f} mm (LoD95 up to {:.2f} mm); tlsmon query "
                            "stable-areas --state unstable lists them",
                            a.supervoxels.size(), a.centre.x(), a.centre.y(), a.centre.z(),
                            2.0 * a.extent, r.stable_areas->persistent_epochs, 1e3 * a.min_change,
                            1e3 * a.max_change, 1e3 * a.max_lod),
                epoch});
        }
    }
    for (const auto& z : r.zones) {
        results.registration_zone_sigmas.push_back({z.zone, z.max_sigma_3d});
    }
    results.planes = plane_rows(r);
    if (r.planes) {
        for (auto& z : plane_zone_results(r.planes->zone_plane, results.planes)) {
            results.zone_results.push_back(std::move(z));
        }
    }
}

std::vector<ZoneResult> plane_zone_results(const std::map<std::string, std::size_t>& zone_plane,
                                           const std::vector<PlaneRow>& rows) {
    constexpr double kArcsecPerRad = 180.0 * 3600.0 / 3.141592653589793;
    constexpr double kLod95 = 1.959963984540054;  // the two-sided 95 % quantile of N(0, 1)
    std::vector<ZoneResult> out;
    for (const auto& [zone, plane] : zone_plane) {
        for (const PlaneRow& p : rows) {
            if (p.plane != static_cast<std::int64_t>(plane) || p.role != "monitored") continue;
            const std::array<std::pair<const char*, double>, 3> quantities{
                {{kPlaneTiltU, kArcsecPerRad}, {kPlaneTiltV, kArcsecPerRad}, {kPlaneShift, 1.0}}};
            for (int k = 0; k < 3; ++k) {
                const double value = p.change[k] * quantities[k].second;
                const double lod = kLod95 * p.sigma[k] * quantities[k].second;
                out.push_back({zone, quantities[k].first, value, lod, p.reference_points,
                               std::fabs(value) > lod});
            }
        }
    }
    return out;
}

std::vector<PlaneRow> plane_rows(const RegistrationResult& r) {
    std::vector<PlaneRow> out;
    if (!r.accepted() || !r.planes || !r.planes->transform) return out;
    const registration::RigidTransform& T = *r.tested.transform;
    for (const auto& o : r.planes->matched) {
        const auto m =
            registration::plane_misclosure({o.reference, o.epoch}, T.rotation, T.translation);
        PlaneRow p;
        p.plane = static_cast<std::int64_t>(o.plane);
        p.zone = o.zone;
        p.role = o.role;
        for (int k = 0; k < 3; ++k) {
            p.normal[k] = o.reference.normal(k);
            p.centroid[k] = o.reference.centroid(k);
            p.change[k] = m.w(k);
            p.sigma[k] = std::sqrt(o.misclosure.cofactor(k, k));
        }
        p.reference_points = static_cast<std::int64_t>(o.reference.points);
        p.epoch_points = static_cast<std::int64_t>(o.epoch.points);
        // The planes' own cofactor (its prediction's part is nearly the same under a combined
        // transformation, which agreed with theirs).
        p.statistic = m.w.dot(o.misclosure.cofactor.ldlt().solve(m.w));
        p.critical = o.critical;
        p.significant = p.statistic > p.critical;
        out.push_back(p);
    }
    return out;
}

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

}  // namespace tlsmon
