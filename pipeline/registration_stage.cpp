#include "pipeline/registration_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "algorithms/registration/checkerboard_centre.hpp"
#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/point_to_plane.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "algorithms/registration/sphere_fit.hpp"
#include "core/error.hpp"
#include "core/group_refractivity.hpp"
#include "core/payload.hpp"
#include "pipeline/icp_registration.hpp"
#include "pipeline/registration_on_planes.hpp"
#include "pipeline/registration_rows.hpp"
#include "pipeline/stable_area_registration.hpp"
#include "pipeline/target_window.hpp"

namespace tlsmon {

namespace reg = registration;

const char* name_of(reg::TargetUse use) {
    switch (use) {
        case reg::TargetUse::used:
            return "used";
        case reg::TargetUse::not_usable:
            return "not_usable";
        case reg::TargetUse::excluded_outlier:
            return "excluded_outlier";
        case reg::TargetUse::suspect:
            return "suspect";
    }
    return "unknown";
}

const char* name_of(reg::RegistrationStatus status) {
    switch (status) {
        case reg::RegistrationStatus::accepted:
            return "accepted";
        case reg::RegistrationStatus::accepted_scaled:
            return "accepted_scaled";
        case reg::RegistrationStatus::global_test_failed:
            return "global_test_failed";
        case reg::RegistrationStatus::too_few_targets:
            return "too_few_targets";
        case reg::RegistrationStatus::degenerate_geometry:
            return "degenerate_geometry";
        case reg::RegistrationStatus::outlier_not_excludable:
            return "outlier_not_excludable";
        case reg::RegistrationStatus::outlier_not_identifiable:
            return "outlier_not_identifiable";
        case reg::RegistrationStatus::planes_refused:
            return "planes_refused";
        case reg::RegistrationStatus::stable_areas_refused:
            return "stable_areas_refused";
    }
    return "unknown";
}

namespace {

constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);

// The target's centre in one scan, or why not.
TargetMeasurement measure_in(const TargetConfig& target, const Scan& scan,
                             const Eigen::Vector3d& predicted, const RegistrationConfig& config) {
    TargetMeasurement m;
    m.name = target.name;
    m.kind = target.kind;
    m.viewpoint = scan.scanner_position();
    // Wide enough for the whole target: a board's fit takes the points within 0.75·size.
    const double radius =
        std::max(config.search_radius,
                 target.kind == TargetKind::sphere ? 2.0 * target.radius : 0.8 * target.size);
    const TargetWindow w = points_near(scan, predicted, radius);
    m.points = w.indices.size();
    std::vector<Eigen::Vector3d> xyz;
    xyz.reserve(w.indices.size());
    for (const auto i : w.indices) xyz.push_back(scan.xyz[i]);
    if (target.kind == TargetKind::sphere) {
        reg::SphereFitParams p;
        p.radius = target.radius;
        p.seed = std::hash<std::string>{}(target.name) | 1u;
        // A known radius leaves three unknowns: 20 points on a far sphere's cap (a 0.15 m
        // sphere at 98.5 m and 0.03° gives 27) still fix its centre to a fraction of a mm.
        p.min_points = 20;
        p.mount = target.mount;
        p.mount_cap_deg = target.mount_cap_deg;
        const reg::SphereFit f = reg::fit_sphere(xyz, predicted, p);
        if (!f.found()) {
            m.status = f.status == reg::SphereFitStatus::bad_fit ? "bad_fit" : "not_found";
            m.reason =
                std::string(reg::describe(f.reason)) + (f.detail.empty() ? "" : ": ") + f.detail;
            return m;
        }
        m.status = "found";
        m.centre = f.centre;
        m.covariance = f.centre_covariance;
    } else {
        if (scan.intensity.size() != scan.size()) {
            m.reason = "the scan has no intensity, which a checkerboard's centre needs";
            return m;
        }
        std::vector<float> intensity;
        intensity.reserve(w.indices.size());
        for (const auto i : w.indices) intensity.push_back(scan.intensity[i]);
        CheckerboardSearch s;
        s.approximate_centre = predicted;
        s.size = target.size;
        s.viewpoint = scan.scanner_position();
        try {
            const CheckerboardCentre c = checkerboard_centre(xyz, intensity, s);
            m.centre = c.centre;
            m.covariance = c.covariance;
        } catch (const Error& e) {
            m.reason = e.what();
            return m;
        }
        const double offset = (m.centre - predicted).norm();
        if (offset > 0.05) {
            m.reason =
                fmt::format("centre {:.1f} mm from the prediction (at most 50 mm)", 1e3 * offset);
            return m;
        }
        m.status = "found";
    }
    m.covariance +=
        config.centre_sigma_floor * config.centre_sigma_floor * Eigen::Matrix3d::Identity();
    return m;
}

// The canonical text of everything the reference centres depend on.
std::string reference_parameters(const RegistrationConfig& c) {
    std::string s =
        fmt::format("search_radius={:.17g};floor={:.17g}", c.search_radius, c.centre_sigma_floor);
    for (const auto& t : c.targets) {
        s +=
            fmt::format(";{}:{}:{:.17g}:{:.17g}:{:.17g},{:.17g},{:.17g}", t.name, to_string(t.kind),
                        t.radius, t.size, t.approximate.x(), t.approximate.y(), t.approximate.z());
        if (t.kind == TargetKind::sphere) {
            s += fmt::format(":mount {:.17g},{:.17g},{:.17g}@{:.17g}", t.mount.x(), t.mount.y(),
                             t.mount.z(), t.mount_cap_deg);
        }
        if (t.surveyed) {
            s += fmt::format(":surveyed {:.17g},{:.17g},{:.17g}±{:.17g}", t.surveyed->x(),
                             t.surveyed->y(), t.surveyed->z(), t.surveyed_sigma);
        }
    }
    return s;
}

}  // namespace

TargetMeasurement measure_target(const TargetConfig& target, const std::vector<Scan>& scans,
                                 const Eigen::Vector3d& predicted,
                                 const RegistrationConfig& config) {
    TargetMeasurement best;
    best.name = target.name;
    best.kind = target.kind;
    best.reason = "no scan in the file";
    for (const auto& scan : scans) {
        TargetMeasurement m = measure_in(target, scan, predicted, config);
        const bool better = m.found() ? !best.found() || m.points > best.points
                                      : !best.found() && m.points >= best.points;
        if (better) best = std::move(m);
    }
    return best;
}

ReferenceTargets measure_reference_targets(const RegistrationConfig& config,
                                           const std::vector<Scan>& scans) {
    ReferenceTargets r;
    for (const auto& t : config.targets) {
        if (t.surveyed) {
            TargetMeasurement m;
            m.name = t.name;
            m.kind = t.kind;
            m.status = "found";
            m.reason = "surveyed";
            m.centre = *t.surveyed;
            m.covariance = t.surveyed_sigma * t.surveyed_sigma * Eigen::Matrix3d::Identity();
            r.targets.push_back(m);
        } else {
            r.targets.push_back(measure_target(t, scans, t.approximate, config));
        }
    }
    return r;
}

std::string ReferenceTargets::encode() const {
    PayloadWriter w;
    w.put<std::uint64_t>(targets.size());
    for (const auto& t : targets) {
        w.put<std::uint8_t>(t.found() ? 1 : 0);
        w.put<std::uint8_t>(t.kind == TargetKind::sphere ? 0 : 1);
        for (int k = 0; k < 3; ++k) w.put(t.centre[k]);
        for (int k = 0; k < 9; ++k) w.put(t.covariance.data()[k]);
        for (int k = 0; k < 3; ++k) w.put(t.viewpoint[k]);
        w.put<std::uint64_t>(t.points);
        w.put_array(std::vector<char>(t.name.begin(), t.name.end()));
        w.put_array(std::vector<char>(t.reason.begin(), t.reason.end()));
    }
    return w.take();
}

ReferenceTargets ReferenceTargets::decode(std::string_view payload) {
    PayloadReader r(payload);
    ReferenceTargets out;
    const auto n = r.get<std::uint64_t>();
    if (n > payload.size()) throw Error("reference cache payload: absurd target count");
    for (std::uint64_t i = 0; i < n; ++i) {
        TargetMeasurement t;
        t.status = r.get<std::uint8_t>() ? "found" : "not_found";
        t.kind = r.get<std::uint8_t>() ? TargetKind::checkerboard : TargetKind::sphere;
        for (int k = 0; k < 3; ++k) t.centre[k] = r.get<double>();
        for (int k = 0; k < 9; ++k) t.covariance.data()[k] = r.get<double>();
        for (int k = 0; k < 3; ++k) t.viewpoint[k] = r.get<double>();
        t.points = r.get<std::uint64_t>();
        const auto name = r.get_array<char>();
        const auto reason = r.get_array<char>();
        t.name.assign(name.begin(), name.end());
        t.reason.assign(reason.begin(), reason.end());
        out.targets.push_back(std::move(t));
    }
    r.finish();
    return out;
}

void confirm_exclusions(RegistrationResult& r, const std::map<std::string, int>& runs,
                        int confirm) {
    std::vector<std::string> confirmed;
    for (auto& name : r.newly_excluded) {
        const auto it = runs.find(name);
        const int failed = 1 + (it == runs.end() ? 0 : it->second);
        (failed >= confirm ? confirmed : r.outliers).push_back(name);
    }
    r.newly_excluded = std::move(confirmed);
}

RegistrationResult register_epoch(const RegistrationConfig& config,
                                  const ReferenceTargets& reference, const std::vector<Scan>& scans,
                                  const std::set<std::string>& excluded,
                                  const RangeScales& scales) {
    if (reference.targets.size() != config.targets.size()) {
        throw Error("the reference centres do not match the configured targets");
    }
    RegistrationResult out;
    out.reference = reference.targets;
    if (scales.epoch && scales.reference) {
        out.epoch_range_scale = scales.epoch;
        out.reference_range_scale = scales.reference;
        out.atmosphere = fmt::format(
            "ranges corrected to the measured air: epoch {:+.2f} ppm, reference {:+.2f} ppm",
            (*scales.epoch - 1) * 1e6, (*scales.reference - 1) * 1e6);
    } else if (scales.epoch || scales.reference) {
        out.atmosphere = std::string("not corrected: no meteo for the ") +
                         (scales.epoch ? "reference epoch" : "epoch");
    } else {
        out.atmosphere = "not corrected: no meteo";
    }
    std::vector<reg::TargetPair> pairs;
    for (std::size_t i = 0; i < config.targets.size(); ++i) {
        const auto& t = config.targets[i];
        const auto& ref = reference.targets[i];
        // Predicted where it was in the reference epoch: the drift moves it by millimetres.
        const Eigen::Vector3d predicted = ref.found() ? ref.centre : t.approximate;
        TargetMeasurement m = measure_target(t, scans, predicted, config);
        // The air: ranges scaled back by 1/scale about the scanner (both or neither).
        const bool correct = scales.epoch && scales.reference;
        const auto corrected = [](const TargetMeasurement& t, double scale) {
            return Eigen::Vector3d(t.viewpoint + (t.centre - t.viewpoint) / scale);
        };
        reg::TargetPair p;
        p.centres.reference = correct ? corrected(ref, *scales.reference) : ref.centre;
        p.centres.reference_covariance = ref.covariance;
        p.centres.epoch = correct ? corrected(m, *scales.epoch) : m.centre;
        p.centres.epoch_covariance = m.covariance;
        p.usable = ref.found() && m.found() && !excluded.count(t.name);
        if (!ref.found()) {
            p.centres.epoch_covariance = Eigen::Matrix3d::Identity();
            p.centres.reference_covariance = Eigen::Matrix3d::Identity();
            if (m.reason.empty()) m.reason = "not found in the reference epoch: " + ref.reason;
        }
        if (excluded.count(t.name)) {
            m.reason = "excluded as moved until it is re-surveyed";
            if (m.found()) m.status = "excluded";
        }
        if (!m.found() && m.status != "excluded") {
            p.centres.epoch_covariance = Eigen::Matrix3d::Identity();
        }
        pairs.push_back(p);
        out.measured.push_back(std::move(m));
    }
    reg::TargetTestParams params;
    params.global_alpha = config.global_alpha;
    params.global_reject_alpha = std::min(config.global_reject_alpha, config.global_alpha);
    params.target_alpha = config.target_alpha;
    params.min_targets = static_cast<std::size_t>(config.min_targets);
    params.adjustment.scaling = config.covariance_scaling;
    out.tested = reg::register_with_tests(pairs, params);
    for (std::size_t i = 0; i < out.tested.targets.size(); ++i) {
        const auto& v = out.tested.targets[i];
        if (v.use == reg::TargetUse::excluded_outlier) {
            out.newly_excluded.push_back(config.targets[i].name);
        }
        if (v.use == reg::TargetUse::used && out.tested.transform) {
            ++out.used;
            const double len = v.residual.norm();
            out.rms += len * len;
            out.max_residual = std::max(out.max_residual, len);
        }
    }
    out.rms = out.used ? std::sqrt(out.rms / out.used) : 0.0;
    if (!out.tested.accepted() || !out.tested.transform) return out;
    const reg::RigidTransform& T = *out.tested.transform;
    if (out.rms > config.max_rms) {
        out.gate = fmt::format(
            "RMS of the target residuals {:.2f} mm above registration.max_rms "
            "= {:.2f} mm",
            1e3 * out.rms, 1e3 * config.max_rms);
    } else {
        out.gate = sigma_gate(config, T);
    }
    out.zones = zone_sigmas(config, T);
    return out;
}

std::string sigma_gate(const RegistrationConfig& config, const reg::RigidTransform& T) {
    const auto sig = T.sigmas();
    const char* angles[] = {"ω", "φ", "κ"};
    for (int k = 0; k < 3; ++k) {
        if (sig(k) / kArcsec > config.max_sigma_angle_arcsec) {
            return fmt::format("σ of {} {:.1f}″ above registration.max_sigma_angle_arcsec = {}″",
                               angles[k], sig(k) / kArcsec, config.max_sigma_angle_arcsec);
        }
    }
    const char* axes[] = {"tx", "ty", "tz"};
    for (int k = 0; k < 3; ++k) {
        if (sig(3 + k) > config.max_sigma_translation) {
            return fmt::format(
                "σ of {} {:.2f} mm above registration.max_sigma_translation = {:.2f} mm", axes[k],
                1e3 * sig(3 + k), 1e3 * config.max_sigma_translation);
        }
    }
    return "";
}

std::vector<ZoneRegistrationSigma> zone_sigmas(const RegistrationConfig& config,
                                               const reg::RigidTransform& T) {
    std::vector<ZoneRegistrationSigma> out;
    for (const auto& z : config.zones) {
        ZoneRegistrationSigma s{z.name, 0.0};
        for (int c = 0; c < 8; ++c) {
            const Eigen::Vector3d p = z.box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
            s.max_sigma_3d =
                std::max(s.max_sigma_3d, std::sqrt(reg::registration_covariance_at(T, p).trace()));
        }
        out.push_back(s);
    }
    return out;
}

std::string join_estimate(const RegistrationConfig& config, RegistrationResult& result,
                          const reg::RigidTransform& other, const std::string& kept,
                          std::optional<double>& agreement) {
    constexpr double kAgreementAlpha = 0.001;
    const reg::RigidTransform& accepted = *result.tested.transform;
    agreement = reg::transform_difference_statistic(accepted, other);
    const double limit = reg::chi_square_quantile(1.0 - kAgreementAlpha, 6);
    if (*agreement > limit) {
        return fmt::format(
            "disagrees with the {}: χ² {:.1f} of the difference above {:.1f} (α {}); the {}' "
            "transformation is kept",
            kept, *agreement, limit, kAgreementAlpha, kept);
    }
    result.tested.transform = reg::combine_transforms(accepted, other);
    result.gate = sigma_gate(config, *result.tested.transform);
    return "";
}

bool stand_in(const RegistrationConfig& config, RegistrationResult& result,
              const std::optional<reg::RigidTransform>& estimate, std::string& refused,
              const std::string& accepted_reason, reg::RegistrationStatus status,
              const std::string& before) {
    if (refused.empty()) refused = sigma_gate(config, *estimate);
    const bool taken = refused.empty();
    result.tested.status = taken ? reg::RegistrationStatus::accepted : status;
    result.tested.reason = taken ? accepted_reason : refused;
    if (!before.empty()) result.tested.reason += "; " + before;
    if (taken) {
        result.tested.transform = estimate;
    } else {
        result.tested.transform.reset();
    }
    result.gate.clear();
    return taken;
}

std::optional<double> measured_range_scale(const RegistrationConfig& config,
                                           const std::optional<MeteoSidecar>& meteo) {
    if (config.atmosphere == AtmosphereCorrection::off || !meteo || !meteo->values) {
        return std::nullopt;
    }
    const auto& v = *meteo->values;
    const double n_true = group_refractivity(config.scanner_wavelength_nm, v.air_temperature_c,
                                             v.pressure_hpa, v.relative_humidity_pct);
    const double n_setting =
        group_refractivity(config.scanner_wavelength_nm, config.scanner_temperature_c,
                           config.scanner_pressure_hpa, config.scanner_humidity_pct);
    return range_scale(n_true, n_setting);
}

StageVerdict RegistrationStage::run(StageContext& ctx) const {
    const RegistrationConfig& config = config_;
    // The reference is its own datum; only the targets' reference centres are measured in it.
    const bool measures_targets = config.uses_targets() && !config.targets.empty();
    if (!can_register(config) || (ctx.is_reference() && !measures_targets)) {
        ctx.results.registration = datum_without_registration(ctx.is_reference());
        return StageVerdict{"", ctx.results.registration->reason};
    }
    RegistrationResult result;
    const StageVerdict verdict = measure(ctx, result);
    record_registration(result, verdict, ctx.input.epoch.id, ctx.results);
    if (!verdict.ran()) return verdict;
    ctx.outputs = outputs_of(result, ctx.input);
    return verdict;
}

StageOutputs RegistrationStage::outputs_of(const RegistrationResult& result,
                                           const EpochInput& input) {
    StageOutputs outputs;
    outputs.to_reference = result.tested.transform;
    if (result.epoch_range_scale && !input.scans->empty()) {
        outputs.range_scale = *result.epoch_range_scale;
        outputs.scanner = input.scans->front().scanner_position();
        outputs.reference_range_scale = result.reference_range_scale.value_or(1.0);
    }
    return outputs;
}

StageVerdict RegistrationStage::measure(StageContext& ctx, RegistrationResult& result) const {
    const RegistrationConfig& config = config_;
    // The reference centres: measured once in the reference epoch (or surveyed), cached.
    // With `method = "planes"` the targets are not measured at all.
    RegistrationConfig targets = config;
    if (!config.uses_targets()) targets.targets.clear();
    const auto centres = ctx.cache.get<ReferenceTargets>(
        ctx.reference,
        ProductKey{"registration.targets", reference_parameters(targets),
                   ReferenceTargets::kFormatVersion},
        [&](const std::vector<Scan>& scans) { return measure_reference_targets(targets, scans); });
    // The air of both epochs, each range corrected from the scanner's setting.
    const std::optional<MeteoSidecar>& reference_meteo =
        ctx.is_reference() ? ctx.input.meteo : ctx.history.reference_meteo;
    const RangeScales scales{measured_range_scale(config, ctx.input.meteo),
                             measured_range_scale(config, reference_meteo)};
    result =
        register_epoch(targets, *centres, *ctx.input.scans, ctx.history.excluded_targets, scales);
    confirm_exclusions(result, ctx.history.outlier_runs, config.confirm_exclusion_epochs);
    // registration.method on planes, then registration.icp.
    apply_planes(config, ctx.input, ctx.reference, ctx.cache, scales, result,
                 ctx.history.last_transform);
    apply_stable_areas(config, ctx.input, ctx.reference, ctx.cache, scales, result, ctx.history);
    apply_icp(config, ctx.input, ctx.reference, ctx.cache, scales, result);
    StageVerdict verdict;
    std::string not_found;
    for (const auto& m : result.measured) {
        if (!m.found() && m.status != "excluded") {
            not_found +=
                (not_found.empty() ? "" : "; ") + m.name + " " + m.status + " (" + m.reason + ")";
        }
    }
    for (const auto& name : result.newly_excluded) {
        not_found += (not_found.empty() ? "" : "; ") + name + " moved, excluded";
    }
    for (const auto& name : result.outliers) {
        not_found += (not_found.empty() ? "" : "; ") + name + " failed its outlier test";
    }
    if (!result.tested.accepted()) {
        verdict.rejected = std::string(reg::describe(result.tested.status)) + ": " +
                           result.tested.reason + (not_found.empty() ? "" : " [" + not_found + "]");
        return verdict;
    }
    if (!result.gate.empty()) {
        verdict.rejected = "quality gate: " + result.gate;
        return verdict;
    }
    const auto sig = result.tested.transform->sigmas();
    const auto& planes = result.planes;
    const auto& stable = result.stable_areas;
    if (stable && stable->used && stable->role == "alone") {
        verdict.note = fmt::format(
            "stable areas: {} of {} supervoxels stable ({:.0f} % of the voxels), {} rounds",
            stable->stable, stable->stable + stable->unstable, 100.0 * stable->stable_share,
            stable->iterations);
    } else if (planes && planes->used && planes->role == "alone") {
        verdict.note =
            fmt::format("{} planes ({} moved, {} in zones), Ω {:.1f} ≤ {:.1f}", planes->in_datum,
                        planes->moved, planes->monitored, planes->last_omega, planes->last_limit);
    } else {
        verdict.note = fmt::format("{} targets, RMS {:.2f} mm", result.used, 1e3 * result.rms);
        if (planes && planes->used) {
            verdict.note += fmt::format(" + {} planes ({} moved)", planes->in_datum, planes->moved);
        }
    }
    verdict.note += fmt::format(", σ κ {:.1f}″, σ t {:.2f}/{:.2f}/{:.2f} mm", sig(2) / kArcsec,
                                1e3 * sig(3), 1e3 * sig(4), 1e3 * sig(5));
    if (result.tested.status == reg::RegistrationStatus::accepted_scaled) {
        verdict.note += fmt::format("; global test failed, covariance scaled by s0² {:.2f}",
                                    result.tested.global.variance_factor);
    }
    if (!not_found.empty()) verdict.note += " [" + not_found + "]";
    if (planes && !planes->used) verdict.note += "; planes not used: " + planes->refused;
    if (stable && stable->used && stable->role == "joint") {
        verdict.note += fmt::format(" + stable areas ({} supervoxels)", stable->stable);
    }
    if (stable && !stable->used) verdict.note += "; stable areas not used: " + stable->refused;
    verdict.note += "; atmosphere " + result.atmosphere;
    if (result.icp) verdict.note += "; " + registration_method(result);
    return verdict;
}

}  // namespace tlsmon
