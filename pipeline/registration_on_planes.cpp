#include "pipeline/registration_on_planes.hpp"

#include <fmt/format.h>

#include <chrono>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/plane_matching_without_prior.hpp"
#include "algorithms/registration/point_to_plane.hpp"
#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

namespace reg = registration;

namespace {

double milliseconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string detection_parameters(const PlaneConfig& c) {
    const reg::PlaneDetectionParams p = c.detection();
    return fmt::format(
        "a={:.17g};b={:.17g};angular={:.17g};flatness={:.17g};alpha={:.17g};tile={};"
        "min_cells={};min_points={};normal={:.17g};merge={:.17g};edge={}",
        p.noise.range_sigma_a, p.noise.range_sigma_b_ppm, p.noise.angular_sigma_arcsec, p.flatness,
        p.alpha, p.tile, p.min_cells, p.min_points, p.max_normal_sigma_arcsec, p.merge_alpha,
        p.edge_cells);
}

// The plane with its ranges scaled by 1/scale about the scanner: the centroid moves along its
// beam, the normal keeps its direction (a scaling about a point maps a plane to a parallel
// one).
reg::FittedPlane range_corrected(reg::FittedPlane p, const Eigen::Vector3d& scanner, double scale) {
    p.centroid = scanner + (p.centroid - scanner) / scale;
    return p;
}

void put_vector(PayloadWriter& w, const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) w.put(v(k));
}

Eigen::Vector3d get_vector(PayloadReader& r) {
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v(k) = r.get<double>();
    return v;
}

// The zone a point lies in ("" for none), in the configuration's order.
std::string zone_of(const RegistrationConfig& config, const Eigen::Vector3d& p) {
    for (const auto& z : config.zones) {
        if (z.contains(p)) return z.name;
    }
    return "";
}

// Matched from `start`, the congruence test on the planes outside the zones: m's matches,
// roles, figures and transformation, or m.refused.
void match_and_test(const RegistrationConfig& config, const std::vector<reg::FittedPlane>& ref,
                    const std::vector<reg::FittedPlane>& epoch, const reg::RigidTransform& start,
                    PlaneMeasurement& m) {
    const PlaneConfig& c = config.planes;
    const auto matches = reg::match_planes(ref, epoch, start, c.matching());
    std::vector<reg::PlaneCorrespondence> pairs;
    std::vector<bool> candidate;
    for (const auto& match : matches) {
        PlaneObservation o;
        o.plane = match.reference;
        o.reference = ref[match.reference];
        o.epoch = epoch[match.epoch];
        o.zone = zone_of(config, o.reference.centroid);
        o.role = o.zone.empty() ? "datum" : "monitored";
        candidate.push_back(o.zone.empty());
        pairs.push_back({o.reference, o.epoch});
        m.matched.push_back(std::move(o));
    }
    const auto candidates = static_cast<int>(std::count(candidate.begin(), candidate.end(), true));
    if (candidates < c.min_planes) {
        m.refused = fmt::format(
            "{} planes matched outside the zones, fewer than registration.plane_min_planes = {} "
            "({} in the reference, {} in the epoch, {} matched)",
            candidates, c.min_planes, m.reference_planes, m.epoch_planes, m.matched.size());
        return;
    }
    reg::CongruenceResult test;
    try {
        test = reg::congruence_test(pairs, start, c.congruence(), candidate);
    } catch (const Error& e) {
        m.refused = e.what();
        return;
    }
    m.first_omega = test.global_omega.front();
    m.first_limit = test.global_limit.front();
    m.last_omega = test.global_omega.back();
    m.last_limit = test.global_limit.back();
    m.congruent = test.congruent;
    for (const auto i : test.moved) m.matched[i].role = "moved";
    const double critical = reg::chi_square_quantile(1.0 - c.alpha, 3);
    for (std::size_t i = 0; i < m.matched.size(); ++i) {
        auto& o = m.matched[i];
        o.misclosure = test.adjustment.planes[i];
        o.critical = critical;
        m.in_datum += o.role == "datum";
        m.moved += o.role == "moved";
        m.monitored += o.role == "monitored";
    }
    m.transform = test.adjustment.transform;
    if (!test.congruent) {
        m.refused = fmt::format("the congruence test found no congruent set: {}", test.note);
    }
}

StationChange station_change_from(const reg::RigidTransform& start, const reg::RigidTransform& T,
                                  std::size_t support) {
    return {(T.translation - start.translation).norm(),
            Eigen::AngleAxisd(T.rotation * start.rotation.transpose()).angle() * 180.0 /
                3.141592653589793,
            support};
}

std::shared_ptr<const ReferencePlanes> reference_planes(const RegistrationConfig& config,
                                                        ReferenceEpoch& reference,
                                                        ReferenceCache& cache) {
    return cache.get<ReferencePlanes>(
        reference, ProductKey{"registration.planes", detection_parameters(config.planes), 1},
        [&](const std::vector<Scan>& scans) { return detect_scan_planes(config.planes, scans); });
}

// The planes' own estimate from `start`; when that fails, from the matching without a prior,
// which is a station change if it puts the scanner beyond the matching's tolerances from
// `start`.
PlaneMeasurement measure_planes(const RegistrationConfig& config, const ReferencePlanes& reference,
                                const std::vector<Scan>& scans, const RangeScales& scales,
                                const reg::RigidTransform& start) {
    const PlaneConfig& c = config.planes;
    PlaneMeasurement m;
    const bool correct = scales.epoch && scales.reference;
    auto t0 = std::chrono::steady_clock::now();
    ReferencePlanes epoch = detect_scan_planes(c, scans);
    m.detection_ms = milliseconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    std::vector<reg::FittedPlane> ref = reference.planes;
    if (correct) {
        for (auto& p : ref) p = range_corrected(p, reference.viewpoint, *scales.reference);
        for (auto& p : epoch.planes) p = range_corrected(p, epoch.viewpoint, *scales.epoch);
    }
    m.reference_planes = ref.size();
    m.epoch_planes = epoch.planes.size();
    for (std::size_t i = 0; i < ref.size(); ++i) {  // largest first
        const std::string zone = zone_of(config, ref[i].centroid);
        if (!zone.empty()) m.zone_plane.try_emplace(zone, i);
    }
    const PlaneMeasurement empty = m;
    match_and_test(config, ref, epoch.planes, start, m);
    if (!m.refused.empty()) {
        if (const auto free = reg::match_planes_without_prior(ref, epoch.planes)) {
            const reg::RigidTransform& T = free->approximate;
            const StationChange change = station_change_from(start, T, free->support);
            PlaneMeasurement retry = empty;
            match_and_test(config, ref, epoch.planes, T, retry);
            if (retry.refused.empty() &&
                (change.shift_m > c.max_offset || change.turn_deg > c.max_angle_deg)) {
                retry.station_change = change;
                m = std::move(retry);
            } else if (!retry.refused.empty()) {
                m.refused += fmt::format(
                    "; matched without a prior ({} planes explained, the scanner {:.3f} m and "
                    "{:.2f}° away): {}",
                    free->support, change.shift_m, change.turn_deg, retry.refused);
            }
        } else {
            m.refused +=
                "; the matching without a prior found no pose either (too few planes, "
                "or none facing sideways to fix the heading)";
        }
    }
    m.adjustment_ms = milliseconds_since(t0);
    return m;
}

}  // namespace

std::string describe(const StationChange& c) {
    return fmt::format(
        "station change: the scanner stands {:.3f} m and {:.2f}° from the last accepted "
        "registration's pose; matched without a prior ({} planes explained)",
        c.shift_m, c.turn_deg, c.support);
}

std::string ReferencePlanes::encode() const {
    PayloadWriter w;
    w.put<std::uint64_t>(planes.size());
    for (const auto& p : planes) {
        put_vector(w, p.normal);
        put_vector(w, p.centroid);
        for (int k = 0; k < 9; ++k) w.put(p.normal_covariance.data()[k]);
        w.put(p.centroid_variance);
        w.put(p.point_sigma);
        w.put(p.residual_sigma);
        w.put<std::uint64_t>(p.points);
        put_vector(w, p.axis_long);
        put_vector(w, p.axis_short);
        w.put(p.extent_long);
        w.put(p.extent_short);
    }
    put_vector(w, viewpoint);
    return w.take();
}

ReferencePlanes ReferencePlanes::decode(std::string_view payload) {
    PayloadReader r(payload);
    ReferencePlanes out;
    const auto n = r.get<std::uint64_t>();
    if (n > payload.size()) throw Error("reference cache payload: absurd plane count");
    for (std::uint64_t i = 0; i < n; ++i) {
        reg::FittedPlane p;
        p.normal = get_vector(r);
        p.centroid = get_vector(r);
        for (int k = 0; k < 9; ++k) p.normal_covariance.data()[k] = r.get<double>();
        p.centroid_variance = r.get<double>();
        p.point_sigma = r.get<double>();
        p.residual_sigma = r.get<double>();
        p.points = r.get<std::uint64_t>();
        p.axis_long = get_vector(r);
        p.axis_short = get_vector(r);
        p.extent_long = r.get<double>();
        p.extent_short = r.get<double>();
        out.planes.push_back(p);
    }
    out.viewpoint = get_vector(r);
    r.finish();
    return out;
}

ReferencePlanes detect_scan_planes(const PlaneConfig& config, const std::vector<Scan>& scans) {
    ReferencePlanes out;
    if (!scans.empty()) out.viewpoint = scans.front().scanner_position();
    for (const auto& scan : scans) {
        if (!scan.grid) continue;
        for (auto& d : reg::detect_planes(scan, config.detection())) {
            out.planes.push_back(std::move(d.plane));
        }
    }
    std::stable_sort(out.planes.begin(), out.planes.end(),
                     [](const auto& a, const auto& b) { return a.points > b.points; });
    return out;
}

void apply_planes(const RegistrationConfig& config, const ReferencePlanes& reference,
                  const std::vector<Scan>& scans, const RangeScales& scales,
                  RegistrationResult& result, const std::optional<reg::RigidTransform>& prior) {
    if (!config.uses_planes()) return;
    // A targets' RMS beyond the gate is not mended by combining; a σ beyond it may be.
    const bool rms_gate = result.gate.rfind("RMS", 0) == 0;
    const bool joint =
        config.uses_targets() && result.tested.accepted() && result.tested.transform && !rms_gate;
    reg::RigidTransform start = prior.value_or(reg::RigidTransform{});
    if (joint) start = *result.tested.transform;
    PlaneMeasurement m = measure_planes(config, reference, scans, scales, start);
    m.role = joint ? "joint" : "alone";
    if (joint) {
        if (m.refused.empty()) {
            m.refused = join_estimate(config, result, *m.transform, "targets", m.agreement);
            m.used = m.refused.empty();
        }
    } else {
        if (config.uses_targets()) {
            m.targets_status =
                std::string(name_of(result.tested.status)) + ": " + result.tested.reason;
        }
        std::string accepted = fmt::format("registered on {} planes ({} moved, {} in zones)",
                                           m.in_datum, m.moved, m.monitored);
        if (m.station_change) accepted += "; " + describe(*m.station_change);
        m.used =
            stand_in(config, result, m.transform, m.refused, accepted,
                     reg::RegistrationStatus::planes_refused,
                     m.targets_status.empty() ? "" : "targets refused (" + m.targets_status + ")");
    }
    if (m.used) result.zones = zone_sigmas(config, *result.tested.transform);
    result.planes = std::move(m);
}

void apply_planes(const RegistrationConfig& config, const EpochInput& input,
                  ReferenceEpoch& reference, ReferenceCache& cache, const RangeScales& scales,
                  RegistrationResult& result, const std::optional<reg::RigidTransform>& prior) {
    if (!config.uses_planes() || reference.epoch().id == input.epoch.id) return;
    apply_planes(config, *reference_planes(config, reference, cache), *input.scans, scales, result,
                 prior);
}

std::optional<CoarsePose> coarse_pose_from_planes(const RegistrationConfig& config,
                                                  const EpochInput& input,
                                                  ReferenceEpoch& reference, ReferenceCache& cache,
                                                  const RangeScales& scales,
                                                  const reg::RigidTransform& start) {
    const auto planes = reference_planes(config, reference, cache);
    std::vector<reg::FittedPlane> ref = planes->planes;
    ReferencePlanes epoch = detect_scan_planes(config.planes, *input.scans);
    if (scales.epoch && scales.reference) {
        for (auto& p : ref) p = range_corrected(p, planes->viewpoint, *scales.reference);
        for (auto& p : epoch.planes) p = range_corrected(p, epoch.viewpoint, *scales.epoch);
    }
    const auto free = reg::match_planes_without_prior(ref, epoch.planes);
    if (!free) return std::nullopt;
    return CoarsePose{free->approximate,
                      station_change_from(start, free->approximate, free->support)};
}

nlohmann::json station_change_json(const std::optional<StationChange>& c) {
    if (!c) return nullptr;
    return {{"shift_m", c->shift_m}, {"turn_deg", c->turn_deg}, {"support", c->support}};
}

nlohmann::json plane_quality(const PlaneMeasurement& m) {
    return nlohmann::json{
        {"role", m.role},
        {"used", m.used},
        {"refused", m.refused},
        {"reference_planes", m.reference_planes},
        {"epoch_planes", m.epoch_planes},
        {"matched", m.matched.size()},
        {"in_datum", m.in_datum},
        {"moved", m.moved},
        {"monitored", m.monitored},
        {"congruent", m.congruent},
        {"first_omega", m.first_omega},
        {"first_limit", m.first_limit},
        {"last_omega", m.last_omega},
        {"last_limit", m.last_limit},
        {"agreement_chi2", m.agreement ? nlohmann::json(*m.agreement) : nlohmann::json(nullptr)},
        {"targets_status", m.targets_status},
        {"station_change", station_change_json(m.station_change)},
        {"detection_ms", m.detection_ms},
        {"adjustment_ms", m.adjustment_ms}};
}

}  // namespace tlsmon
