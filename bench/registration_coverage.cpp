// Does the registration's σ cover its error at the nominal rate? Scored over many independent
// series, each a reference epoch and one later epoch with its own noise seed: within one
// series every epoch shares the reference epoch's centre errors, so a day of epochs is one
// draw of them, and its coverage says little (docs/calibration.md, "One series is one draw").
// Only the targets' angular windows are rendered (the stage's search window about each
// centre; a target with a detail scan of its own in that scan alone), so hundreds of series
// take seconds. The air is switched off: what is scored is the centres' stochastic model and
// the adjustment, not the meteo correction; `--air` keeps it, with each epoch's range scale
// the truth's (as a site's weather station gives it).
//
//   bench_registration_coverage SCENE [SERIES] [FIRST_SEED] [--floor M] [--scaling S]
//                               [--mount-cap DEG] [--air]
//
// SCENE: `demo` (the scene of `tlsmon demo`: the `small` preset at 0.05° with five spheres),
// `pier`, `hochmosel`, or a scene file. The later epoch of series k is taken 24·frac(0.618·k)
// hours after its reference, so the scanner's drift sweeps its day. `--floor` overrides
// registration.centre_sigma_floor, `--scaling` registration.covariance_scaling (a_priori,
// larger_of or a_posteriori), `--mount-cap` every sphere's mount_cap_deg. Prints, per parameter (ω,
// φ, κ, tx, ty, tz) and pooled, the coverage of the 68 % and 95 % intervals with their Wilson bands
// (as `tlsmon calibration`); the same for the transformation's error at two points of the pier's
// south face (mid-height and 1 m below its top) in x, y and z against the covariance propagated
// there (what every zone figure there carries); and per target the centre's change between
// the two epochs against its truth (the footprint's bias, the same in both, cancels), along
// the line of sight, across it horizontally and vertically: RMS(error/σ) with σ² the two
// fits' variances (floor included) — the stochastic model of the centres, seen before the
// adjustment mixes them.
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/registration/rigid_transform.hpp"
#include "bench/bench_support.hpp"
#include "bench/line_of_sight.hpp"
#include "bench/transform_coverage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/simulator/narrow_window.hpp"
#include "tests/support/simulated_targets.hpp"

namespace {

using namespace tlsmon;
constexpr double kDeg = 180.0 / 3.14159265358979323846;

struct TargetWindows {
    std::vector<Scan> scans;  // one per target
    Eigen::Affine3d header_to_true = Eigen::Affine3d::Identity();
    double range_scale = 1;  // the air's, as the site's weather station gives it
};

// The targets' windows of one epoch: a target's own detail scan where the scene has one,
// else the overview narrowed to the stage's search window about it.
TargetWindows render_targets(const sim::Site& site, int epoch, double hours, double search_radius) {
    TargetWindows out;
    const sim::EpochConditions c = sim::epoch_conditions(site, epoch, hours);
    out.range_scale = c.atmosphere.range_scale;
    const Eigen::Affine3d N = sim::nominal_pose(site.scanner);
    for (const auto& t : site.targets) {
        const auto& details = site.scanner.details;
        const auto own = std::find_if(details.begin(), details.end(),
                                      [&](const sim::DetailScan& d) { return d.name == t.name; });
        sim::RenderedScan r;
        if (own != details.end()) {
            r = sim::render_detail(site, static_cast<std::size_t>(own - details.begin()), c, 1);
        } else {
            sim::Site one = site;
            one.scanner.details.clear();
            const double range = (t.centre - site.scanner.position).norm();
            sim::test::narrow_window(one.scanner, t.centre,
                                     std::atan2(search_radius, range) * kDeg + 0.05);
            r = sim::render_epoch(one, c, 1);
        }
        out.header_to_true = N * r.pose_error.transform() * N.inverse();
        out.scans.push_back(std::move(r.scan));
    }
    return out;
}

struct CentreScore {
    Eigen::Vector3d sum_q2 = Eigen::Vector3d::Zero();  // Σ (error/σ)² per axis
    int n = 0;
};

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args;
    std::optional<double> floor, mount_cap;
    std::string scaling = to_string(RegistrationConfig{}.covariance_scaling);
    bool air = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--floor" && i + 1 < argc)
            floor = std::atof(argv[++i]);
        else if (a == "--mount-cap" && i + 1 < argc)
            mount_cap = std::atof(argv[++i]);
        else if (a == "--scaling" && i + 1 < argc)
            scaling = argv[++i];
        else if (a == "--air")
            air = true;
        else
            args.push_back(a);
    }
    const auto scaling_named = covariance_scaling_named(scaling);
    if (args.empty() || !scaling_named) {
        std::fprintf(stderr,
                     "usage: bench_registration_coverage demo|pier|hochmosel|SCENE.toml "
                     "[SERIES] [FIRST_SEED] [--floor M] [--scaling a_priori|larger_of|"
                     "a_posteriori] [--mount-cap DEG] [--air]\n");
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = bench::process_cpu_seconds();
    sim::Site base = bench::scene_named(args[0]);
    base.atmosphere.enabled = air;
    const int series = args.size() > 1 ? std::atoi(args[1].c_str()) : 200;
    const int first_seed = args.size() > 2 ? std::atoi(args[2].c_str()) : 1000;
    RegistrationConfig config = test::simulated_targets(base);
    if (floor) config.centre_sigma_floor = *floor;
    if (mount_cap)
        for (auto& t : config.targets) t.mount_cap_deg = *mount_cap;
    config.covariance_scaling = *scaling_named;

    bench::TransformScores scores(base.pier);
    std::map<std::string, CentreScore> centres;
    std::vector<double> s0;
    int refused = 0, no_reference = 0;
    std::map<std::string, std::string> missing;  // a reference centre not found: why, once
    for (int k = 0; k < series; ++k) {
        sim::Site site = base;
        site.noise.seed = static_cast<std::uint64_t>(first_seed + k);
        const double hours = 24.0 * std::fmod(0.6180339887 * (k + 1), 1.0);
        const TargetWindows e0 = render_targets(site, 0, 0.0, config.search_radius);
        const TargetWindows e1 = render_targets(site, 1, hours, config.search_radius);
        const ReferenceTargets reference = measure_reference_targets(config, e0.scans);
        for (const TargetMeasurement& t : reference.targets) {
            if (t.found()) continue;
            ++no_reference;
            missing.emplace(t.name, t.reason);
        }
        const RegistrationResult r =
            register_epoch(config, reference, e1.scans, {}, {e1.range_scale, e0.range_scale});
        // Each target's change of centre against the truth's: x₁ − H₁⁻¹·H₀·x₀ maps the
        // reference's measured centre into epoch 1's frame by the exact motion.
        const Eigen::Affine3d exact = e0.header_to_true.inverse() * e1.header_to_true;
        for (std::size_t i = 0; i < r.measured.size(); ++i) {
            const TargetMeasurement& m1 = r.measured[i];
            const TargetMeasurement& m0 = reference.targets[i];
            if (!m1.found() || !m0.found()) continue;
            const Eigen::Vector3d error = m1.centre - exact.inverse() * m0.centre;
            const Eigen::Matrix3d A = bench::sight_axes(m1.centre - m1.viewpoint);
            const Eigen::Matrix3d L = exact.inverse().linear();
            const Eigen::Matrix3d S =
                A * (m1.covariance + L * m0.covariance * L.transpose()) * A.transpose();
            CentreScore& c = centres[m1.name];
            c.sum_q2 += (A * error).cwiseProduct(A * error).cwiseQuotient(S.diagonal());
            ++c.n;
        }
        if (!r.accepted()) {
            std::printf("series %d refused: %s%s\n", k, r.tested.reason.c_str(), r.gate.c_str());
            ++refused;
            continue;
        }
        const registration::RigidTransform& T = *r.tested.transform;
        s0.push_back(T.variance_factor);
        scores.add(exact, T);
    }

    std::printf(
        "%s: %d series from seed %d, centre_sigma_floor %.3f mm, covariance_scaling %s; %d "
        "refused; reference centres not found: %d\n",
        args[0].c_str(), series, first_seed, 1e3 * config.centre_sigma_floor, scaling.c_str(),
        refused, no_reference);
    for (const auto& [name, why] : missing)
        std::printf("  %s not found: %s\n", name.c_str(), why.c_str());
    scores.print("registration:targets");
    if (!s0.empty()) {
        std::sort(s0.begin(), s0.end());
        const auto above = std::count_if(s0.begin(), s0.end(), [](double v) { return v > 1; });
        std::printf("s0²: median %.2f, 10 %% %.2f, 90 %% %.2f; above 1 in %.1f %% of epochs\n",
                    s0[s0.size() / 2], s0[s0.size() / 10], s0[s0.size() * 9 / 10],
                    100.0 * double(above) / double(s0.size()));
    }
    std::printf(
        "centre change against the truth, RMS(error/σ) along the line of sight, across "
        "it horizontally, vertically:\n");
    for (const auto& [name, c] : centres) {
        const Eigen::Vector3d q = (c.sum_q2 / c.n).cwiseSqrt();
        std::printf("  %-4s %4d epochs  %.2f  %.2f  %.2f\n", name.c_str(), c.n, q(0), q(1), q(2));
    }
    std::printf("%.1f s wall, %.1f s CPU\n", bench::seconds_since(t0),
                bench::process_cpu_seconds() - cpu0);
    return 0;
}
