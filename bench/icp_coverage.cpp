// Does the ICP's σ cover its error at the nominal rate? The ICP on stable regions
// (pipeline/icp_registration.hpp, docs/registration.md "ICP on stable regions") scored over
// many independent series, as bench/registration_coverage.cpp scores the targets: per series
// its own noise seed, a reference epoch and one later epoch 24·frac(0.618·k) hours after it
// (the scanner's drift sweeps its day), the ICP from the identity (as the fallback runs it)
// on the site's stable ground (simulator/stable_ground.hpp, what `tlsmon simulate` writes as
// [[stable_region]]s), its six parameters against the exact map H₀⁻¹·H₁ and its error at the
// pier's south face against the covariance propagated there. One figure per parameter and
// series: independent figures, so the Wilson band means what it says. Only the scan's lower
// band that holds the regions is rendered, at `--step` (0.05° unless told); the air is
// switched off (what is scored is the ICP's stochastic model, not the meteo correction).
//
//   bench_icp_coverage SCENE [SERIES] [FIRST_SEED] [--step DEG] [--cluster M]
//                      [--noise all|range|angular|none] [--voxel M] [--max-distance M]
//                      [--without REGION,...]
//
// SCENE: `demo`, `pier`, `hochmosel` or a scene file (bench/transform_coverage.hpp).
// `--cluster` overrides registration.icp_cluster_size, `--voxel` icp_voxel_size and
// `--max-distance` icp_max_correspondence_distance (the gain of docs/registration.md, "The
// error follows the motion", depends on both); `--noise` keeps the scanner's range noise
// alone, its angular noise alone, or neither (the footprint stays); `--without` leaves the
// named stable regions out (which region an error comes from). Prints the coverage
// rows as `tlsmon calibration` does; the pooled rows again with each of the adjustment's
// candidate covariances alone (s0²·N⁻¹, the cells' random effect, the sandwich), of which the ICP
// reports the largest, and the sandwich widened by t(dof, 0.975)/1.96 for its Bell–McCaffrey
// degrees of freedom; each parameter's error against the true motion (a slope is a gain, no
// noise); the σ's inflation over s0²·N⁻¹, the cells' τ and the epoch's re-cuts; why epochs
// were refused.
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "bench/bench_support.hpp"
#include "bench/lower_band.hpp"
#include "bench/transform_coverage.hpp"
#include "pipeline/icp_registration.hpp"
#include "simulator/stable_ground.hpp"
#include "tests/support/stable_band.hpp"

using namespace tlsmon;

int main(int argc, char** argv) {
    std::vector<std::string> args;
    double step = 0.05;
    double cluster = 0, voxel = 0, max_distance = 0;
    std::string noise = "all";
    std::set<std::string> without;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--step" && i + 1 < argc)
            step = std::atof(argv[++i]);
        else if (a == "--cluster" && i + 1 < argc)
            cluster = std::atof(argv[++i]);
        else if (a == "--noise" && i + 1 < argc)
            noise = argv[++i];
        else if (a == "--voxel" && i + 1 < argc)
            voxel = std::atof(argv[++i]);
        else if (a == "--max-distance" && i + 1 < argc)
            max_distance = std::atof(argv[++i]);
        else if (a == "--without" && i + 1 < argc) {
            std::istringstream names(argv[++i]);
            for (std::string name; std::getline(names, name, ',');) without.insert(name);
        } else {
            args.push_back(a);
        }
    }
    if (args.empty() || step <= 0 || voxel < 0 || max_distance < 0 ||
        (noise != "all" && noise != "range" && noise != "angular" && noise != "none")) {
        std::fprintf(stderr,
                     "usage: bench_icp_coverage demo|pier|hochmosel|SCENE.toml [SERIES] "
                     "[FIRST_SEED] [--step DEG] [--cluster M] [--noise all|range|angular|none] "
                     "[--voxel M] [--max-distance M] [--without REGION,...]\n");
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = bench::process_cpu_seconds();
    sim::Site base = bench::scene_named(args[0]);
    base.atmosphere.enabled = false;
    // Which of the scanner's noises the scans carry: to tell what an error comes from.
    if (noise == "none") base.noise.enabled = false;
    if (noise == "range") base.noise.angular_arcsec = 0;
    if (noise == "angular") base.noise.signal_a = base.noise.signal_b_ppm = 0;
    const int series = args.size() > 1 ? std::atoi(args[1].c_str()) : 200;
    const int first_seed = args.size() > 2 ? std::atoi(args[2].c_str()) : 1000;

    RegistrationConfig config;
    config.icp.mode = IcpMode::fallback;
    const auto boxes = sim::stable_ground(base);
    for (const auto& name : without) {
        if (std::none_of(boxes.begin(), boxes.end(),
                         [&](const auto& b) { return b.name == name; })) {
            std::fprintf(stderr,
                         "--without: '%s' is not among the scene's stable regions:", name.c_str());
            for (const auto& b : boxes) std::fprintf(stderr, " %s", b.name.c_str());
            std::fprintf(stderr, "\n");
            return 2;
        }
    }
    for (const auto& b : boxes) {
        if (!without.contains(b.name)) config.icp.regions.push_back({b.name, b.min, b.max});
    }
    if (cluster > 0) config.icp.cluster_size = cluster;
    if (voxel > 0) config.icp.voxel_size = voxel;
    if (max_distance > 0) config.icp.max_correspondence_distance = max_distance;
    const double elevation_max = test::highest_box_elevation_deg(base, boxes) + 0.5;

    bench::TransformScores scores(base.pier);
    // The same transformation with each candidate covariance of the adjustment alone.
    const std::vector<
        std::pair<std::string, registration::Covariance6 registration::PointToPlaneFit::*>>
        candidates{{"independent residuals, s0²·N⁻¹", &registration::PointToPlaneFit::independent},
                   {"the cells' random effect", &registration::PointToPlaneFit::cell_effect},
                   {"cluster-robust sandwich", &registration::PointToPlaneFit::clustered}};
    std::vector<bench::TransformScores> candidate_scores(candidates.size(),
                                                         bench::TransformScores(base.pier));
    // The sandwich with each parameter's σ widened by t(dof, 0.975)/1.96, dof its
    // Bell–McCaffrey degrees of freedom: an interval for a variance of few cells.
    bench::TransformScores t_expanded(base.pier);
    std::vector<std::vector<double>> dofs(6);
    std::vector<double> cell_sigma;
    std::map<std::string, int> refused;
    std::vector<double> inflation, pairs, recuts;
    for (int k = 0; k < series; ++k) {
        const bench::BandSeries s = bench::render_series(base, first_seed, k, elevation_max, step);
        const StableSurface surface = build_stable_surface(config.icp, s.reference.scans);
        const IcpMeasurement m =
            measure_icp(config, surface, s.epoch.scans, Eigen::Matrix4d::Identity());
        if (!m.transform || !m.refused.empty()) {
            ++refused[m.refused.empty() ? "no transformation" : m.refused];
            continue;
        }
        const Eigen::Affine3d exact = s.exact();
        scores.add(exact, *m.transform);
        for (std::size_t c = 0; c < candidates.size(); ++c) {
            candidate_scores[c].add(exact, registration::rigid_transform_from(
                                               m.transform->rotation, m.transform->translation,
                                               (*m.fit).*candidates[c].second));
        }
        {
            Eigen::Matrix<double, 6, 1> f;
            for (int p = 0; p < 6; ++p) {
                const double dof = std::max(1.0, m.fit->clustered_dof(p));
                dofs[p].push_back(dof);
                f(p) = registration::student_t_quantile(0.975, dof) / 1.959964;
            }
            t_expanded.add(exact, registration::rigid_transform_from(
                                      m.transform->rotation, m.transform->translation,
                                      f.asDiagonal() * m.fit->clustered * f.asDiagonal()));
        }
        cell_sigma.push_back(m.fit->cell_sigma);
        inflation.push_back(m.inflation);
        pairs.push_back(static_cast<double>(m.pairs));
        recuts.push_back(m.recuts);
    }

    std::printf(
        "%s: %d series from seed %d, %zu stable regions, band up to %.1f° at %.3f°, "
        "icp_cluster_size %.1f m, icp_voxel_size %.3f m, icp_max_correspondence_distance %.3f m; "
        "%zu scored\n",
        args[0].c_str(), series, first_seed, config.icp.regions.size(), elevation_max, step,
        config.icp.cluster_size, config.icp.voxel_size, config.icp.max_correspondence_distance,
        inflation.size());
    for (const auto& [why, n] : refused) std::printf("  refused %d: %s\n", n, why.c_str());
    scores.print("registration:icp");
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        std::printf("with the covariance of %s alone:\n", candidates[c].first.c_str());
        candidate_scores[c].print("registration:icp", true);
    }
    std::printf("with the sandwich widened by t(dof)/1.96 per parameter:\n");
    t_expanded.print("registration:icp", true);
    if (!inflation.empty()) {
        std::printf("the sandwich's degrees of freedom, median (10 %%):");
        for (auto& d : dofs) {
            std::sort(d.begin(), d.end());
            std::printf(" %.1f (%.1f)", d[d.size() / 2], d[d.size() / 10]);
        }
        std::printf("\n");
        std::sort(inflation.begin(), inflation.end());
        std::sort(pairs.begin(), pairs.end());
        std::printf(
            "inflation (σ over the independent residuals' σ): median %.2f, 10 %% %.2f, 90 %% "
            "%.2f; pairs median %.0f\n",
            inflation[inflation.size() / 2], inflation[inflation.size() / 10],
            inflation[inflation.size() * 9 / 10], pairs[pairs.size() / 2]);
        std::sort(recuts.begin(), recuts.end());
        std::printf("the epoch cut again: median %.0f times, most %.0f\n",
                    recuts[recuts.size() / 2], recuts.back());
        std::sort(cell_sigma.begin(), cell_sigma.end());
        std::printf("the cells' common error τ: median %.3f mm, 90 %% %.3f mm\n",
                    1e3 * cell_sigma[cell_sigma.size() / 2],
                    1e3 * cell_sigma[cell_sigma.size() * 9 / 10]);
    }
    std::printf("%.1f s wall, %.1f s CPU\n", bench::seconds_since(t0),
                bench::process_cpu_seconds() - cpu0);
    return 0;
}
