// Does the registration on stable areas cover its error at the nominal rate? The supervoxel
// registration (pipeline/stable_area_registration.hpp, docs/registration.md "Registration on
// stable areas") scored over many independent series, as bench/icp_coverage.cpp scores the
// ICP: per series its own noise seed, a reference epoch and one later epoch
// 24·frac(0.618·k) hours after it (bench/lower_band.hpp), the supervoxels of the reference,
// the registration from the identity with the scene's stable ground
// (simulator/stable_ground.hpp) as its hints and the pier a zone, its six parameters against
// the exact map H₀⁻¹·H₁ and its error at the pier's south face against the covariance
// propagated there. Only the scan's lower band that holds the ground is rendered, at `--step`
// (0.05° unless told), the air off. Prints the coverage rows as `tlsmon calibration` does,
// the same with each candidate covariance alone, the supervoxels' common error τ, why epochs
// were refused and the five series worst against their own σ.
//
//   bench_stable_area_coverage SCENE [SERIES] [FIRST_SEED] [--step DEG]
//
// SCENE: `demo`, `pier`, `hochmosel` or a scene file (bench/transform_coverage.hpp).
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "bench/lower_band.hpp"
#include "bench/transform_coverage.hpp"
#include "pipeline/stable_area_registration.hpp"
#include "simulator/stable_ground.hpp"
#include "tests/support/stable_band.hpp"

using namespace tlsmon;

int main(int argc, char** argv) {
    std::vector<std::string> args;
    double step = 0.05;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--step" && i + 1 < argc)
            step = std::atof(argv[++i]);
        else
            args.push_back(a);
    }
    if (args.empty() || step <= 0) {
        std::fprintf(stderr,
                     "usage: bench_stable_area_coverage demo|pier|hochmosel|SCENE.toml [SERIES] "
                     "[FIRST_SEED] [--step DEG]\n");
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = bench::process_cpu_seconds();
    sim::Site base = bench::scene_named(args[0]);
    base.atmosphere.enabled = false;
    const int series = args.size() > 1 ? std::atoi(args[1].c_str()) : 200;
    const int first_seed = args.size() > 2 ? std::atoi(args[2].c_str()) : 1000;

    RegistrationConfig config;
    config.method = RegistrationMethod::stable_areas;
    const auto boxes = sim::stable_ground(base);
    for (const auto& b : boxes) config.icp.regions.push_back({b.name, b.min, b.max});
    // The pier is a zone, as on a site: it moves, and never enters the datum.
    const sim::Pier& pier = base.pier;
    config.zones.push_back(
        {"pier",
         Eigen::AlignedBox3d(Eigen::Vector3d(pier.x0 - 0.2, pier.y0 - 0.2, -1.0),
                             Eigen::Vector3d(pier.x1 + 0.2, pier.y1 + 0.2, pier.height + 1.0)),
         {},
         {}});
    const double elevation_max = test::highest_box_elevation_deg(base, boxes) + 0.5;

    bench::TransformScores scores(base.pier);
    // The same transformation with each candidate covariance alone (the reported one is their
    // larger): the last round's s0²·N⁻¹ and sandwich, and the supervoxels' with their cells' τ.
    const std::vector<std::string> candidates{"independent voxels, s0²·N⁻¹",
                                              "cluster-robust sandwich",
                                              "the supervoxels with their cells' τ"};
    std::vector<bench::TransformScores> candidate_scores(candidates.size(),
                                                         bench::TransformScores(base.pier));
    std::map<std::string, int> refused;
    std::vector<double> cell_sigma, inflation, stable;
    struct Worst {
        double z;
        int seed, parameter;
        double error;
        std::size_t stable;
        int rounds;
    };
    std::vector<Worst> worst;
    for (int k = 0; k < series; ++k) {
        const bench::BandSeries s = bench::render_series(base, first_seed, k, elevation_max, step);
        const ReferenceSupervoxels reference =
            build_supervoxels(config.stable_areas, s.reference.scans);
        const StableAreaMeasurement m =
            measure_stable_areas(config, reference, s.epoch.scans, Eigen::Matrix4d::Identity());
        if (!m.transform || !m.refused.empty()) {
            ++refused[m.refused.empty() ? "no transformation" : m.refused];
            continue;
        }
        const Eigen::Affine3d exact = s.exact();
        scores.add(exact, *m.transform);
        if (m.fit && m.supervoxel_covariance) {
            const registration::Covariance6* alone[] = {&m.fit->independent, &m.fit->clustered,
                                                        &*m.supervoxel_covariance};
            for (std::size_t c = 0; c < candidates.size(); ++c) {
                candidate_scores[c].add(
                    exact, registration::rigid_transform_from(m.transform->rotation,
                                                              m.transform->translation, *alone[c]));
            }
        }
        // The series' worst parameter against its own σ, to find what the tails come from.
        const Eigen::Vector<double, 6> error =
            bench::parameters_of(*m.transform) - bench::parameters_of(exact);
        const Eigen::Vector<double, 6> z =
            error.cwiseQuotient(m.transform->sigmas().head<6>()).cwiseAbs();
        Eigen::Index p = 0;
        const double largest = z.maxCoeff(&p);
        worst.push_back(
            {largest, first_seed + k, static_cast<int>(p), error(p), m.stable, m.iterations});
        cell_sigma.push_back(m.cell_sigma);
        inflation.push_back(m.inflation);
        stable.push_back(static_cast<double>(m.stable));
    }

    std::printf(
        "%s: %d series from seed %d, band up to %.1f° at %.3f°, hints %zu boxes; %zu "
        "scored\n",
        args[0].c_str(), series, first_seed, elevation_max, step, boxes.size(), cell_sigma.size());
    for (const auto& [why, n] : refused) std::printf("  refused %d: %s\n", n, why.c_str());
    scores.print("registration:stable_areas");
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        std::printf("with the covariance of %s alone:\n", candidates[c].c_str());
        candidate_scores[c].print("registration:stable_areas", true);
    }
    if (!cell_sigma.empty()) {
        const auto median = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        const auto with_tau =
            std::count_if(cell_sigma.begin(), cell_sigma.end(), [](double tau) { return tau > 0; });
        std::printf(
            "the supervoxels' common error τ: median %.3f mm, significant in %.1f %% of the "
            "epochs; inflation (σ over the independent voxels' σ): median %.2f; stable "
            "supervoxels: median %.0f\n",
            1e3 * median(cell_sigma), 100.0 * static_cast<double>(with_tau) / cell_sigma.size(),
            median(inflation), median(stable));
    }
    std::sort(worst.begin(), worst.end(), [](const Worst& a, const Worst& b) { return a.z > b.z; });
    const char* names[] = {"omega (µrad)", "phi (µrad)", "kappa (µrad)",
                           "tx (mm)",      "ty (mm)",    "tz (mm)"};
    for (std::size_t i = 0; i < std::min<std::size_t>(5, worst.size()); ++i) {
        const Worst& w = worst[i];
        std::printf("worst: seed %d, %s %+.3f, %.1f σ; %zu stable supervoxels, %d rounds\n", w.seed,
                    names[w.parameter], w.error * (w.parameter < 3 ? 1e6 : 1e3), w.z, w.stable,
                    w.rounds);
    }
    std::printf("%.1f s wall, %.1f s CPU\n", bench::seconds_since(t0),
                bench::process_cpu_seconds() - cpu0);
    return 0;
}
