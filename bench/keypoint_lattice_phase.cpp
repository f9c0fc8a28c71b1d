// Does the keypoints' error on the `pier` faces depend on where the epoch's image falls on the
// reference's lattice? A scanner that turns between epochs by a fraction φ of its step shifts
// every pixel of the face by the same φ: an error of the sub-pixel refinement that depends on
// φ (the "pixel locking" of image correlation: Westerweel 1997, Meas. Sci. Technol. 8;
// Schreier, Braasch & Sutton 2000, Opt. Eng. 39) is then common to all of a zone's matches and
// no standard error over them sees it. It did, by up to 0.01 pixel: cubic convolution's phase
// error, until the refinement interpolated by the cubic B-spline (docs/keypoints.md, "The
// lattice's phase").
//
// The faces' window of `pier` at the preset's step (tests/pipeline/keypoint_series.hpp's
// render), nothing moving (the bending held at the reference's, the air off), the scanner
// without drift except one rotation per epoch: about its standing axis (MODE yaw: the face
// shifts in azimuth) or a tilt (MODE tilt: it shifts mostly in elevation), of PHASES steps
// from 0 to (PHASES − 1)/PHASES of a pixel, plus WHOLE pixels. Each epoch is registered by the
// exact map (no registration error) and its zones' figures (the south face and its 10 m
// bands) are scored against the truth over the zone's area (0 up to the pier's uniform
// thermal extension). SEEDS noise seeds from FIRST_SEED, each with its own reference.
//
//   bench_keypoint_lattice_phase yaw|tilt [PHASES=8] [SEEDS=3] [FIRST_SEED=11] [WHOLE=0]
//                                [--without-noise]
//
// --without-noise: the scans without the range, angle and intensity noise, so that only the
// systematic pull is left (with noise, an image moved by a fraction of a pixel samples the
// same noise field at other places, and the figures' noise decorrelates from φ = 0's).
// Prints per seed, phase and zone the figure's error along h and v and its standard error;
// then per phase over seeds and zones the mean error and RMS(error/SE) along h and v.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "pipeline/keypoint_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "tests/pipeline/keypoint_series.hpp"
#include "tests/support/simulated_targets.hpp"

namespace {

using namespace tlsmon;

// The scanner turned by `arcsec`: about its standing axis (yaw), or tilted, at the drift's
// quarter day (hours 6: tilt_x = A, tilt_y = A/2); at the reference (hours 0) not at all.
sim::Site turned(sim::Site site, bool yaw, double arcsec) {
    auto& d = site.drift;
    d.enabled = true;
    d.yaw_jitter_arcsec = d.tilt_jitter_arcsec = d.translation_sigma = 0.0;
    d.yaw_period_hours = 24.0;
    d.yaw_amplitude_arcsec = yaw ? arcsec : 0.0;
    d.tilt_amplitude_arcsec = yaw ? 0.0 : arcsec;
    return site;
}

struct Sum {
    double e = 0, z2 = 0, n = 0;
    void add(double error, double se) { e += error, z2 += (error / se) * (error / se), n += 1; }
};

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args;
    bool noise = true;
    for (int i = 1; i < argc; ++i) {
        if (std::string(argv[i]) == "--without-noise")
            noise = false;
        else
            args.emplace_back(argv[i]);
    }
    const auto arg = [&](std::size_t k, int fallback) {
        return args.size() > k ? std::atoi(args[k].c_str()) : fallback;
    };
    const std::string mode = args.empty() ? "" : args[0];
    const int phases = arg(1, 8), seeds = arg(2, 3), first_seed = arg(3, 11), whole = arg(4, 0);
    if ((mode != "yaw" && mode != "tilt") || phases < 1 || seeds < 1) {
        std::fprintf(stderr,
                     "usage: bench_keypoint_lattice_phase yaw|tilt [PHASES] [SEEDS] [FIRST_SEED] "
                     "[WHOLE] [--without-noise]\n");
        return 2;
    }
    const bool yaw = mode == "yaw";
    const auto t0 = std::chrono::steady_clock::now();
    sim::Site site = sim::preset_pier();
    site.atmosphere.enabled = false;
    site.drift.enabled = false;
    site.noise.enabled = noise;
    const double step = site.scanner.azimuth_step_deg;
    KeypointConfig config;
    config.zones = test::pier_zones(site);
    std::erase_if(config.zones, [](const ZoneShape& z) { return z.name == "west"; });
    // The shift in pixels per arcsecond of the turn, at the south face's middle.
    const Eigen::Vector3d middle(0.5 * (site.pier.x0 + site.pier.x1), site.pier.y0,
                                 0.5 * site.pier.height);
    const int axis = yaw ? 0 : 1;
    const sim::Site probe = turned(site, yaw, 100.0);
    const double per_arcsec =
        std::abs((test::seen_at(probe, sim::epoch_conditions(probe, 1, 6.0), middle) -
                  test::seen_at(probe, sim::epoch_conditions(probe, 0, 0.0), middle))[axis]) /
        step / 100.0;
    std::printf("%s: %.4f pixel per arcsecond at the south face's middle (step %.3f°)\n",
                mode.c_str(), per_arcsec, step);
    std::vector<Sum> h(phases), v(phases);
    std::printf(
        "seed phase  Δaz px  Δel px | zone      kept | error h ± SE (mm)  | error v ± SE\n");
    for (int s = 0; s < seeds; ++s) {
        site.noise.seed = static_cast<std::uint64_t>(first_seed + s);
        const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
        const std::vector<Scan> s0{test::render_window(site, c0, step)};
        const KeypointReference ref = prepare_keypoint_reference(config, s0);
        const std::vector<std::vector<Eigen::Vector3d>> cells = test::zone_cells(config, ref, s0);
        for (int j = 0; j < phases; ++j) {
            const double pixels = whole + double(j) / phases;
            const sim::Site sj = turned(site, yaw, pixels / per_arcsec);
            sim::EpochConditions cj = sim::epoch_conditions(sj, 1, 6.0);
            cj.bending = c0.bending;
            const std::vector<Scan> si{test::render_window(sj, cj, step)};
            const Eigen::Vector2d shift =
                (test::seen_at(sj, cj, middle) - test::seen_at(sj, c0, middle)) / step;
            const StageOutputs o = test::exact_outputs(sj, c0, cj, si[0]);
            KeypointEpoch measured = measure_keypoints(config, ref, si, o);
            const KeypointSegmentsResult segments =
                keypoint_segments(config, ref, std::move(measured.matches), o);
            for (std::size_t z = 0; z < segments.segments.size(); ++z) {
                const auto& d = segments.segments[z].displacement;
                const auto& w = d.wall;
                if (!d.defined() || !w.defined() || cells[z].empty()) continue;
                const Eigen::Vector3d truth =
                    test::zone_truth(cells[z], w, [&](const Eigen::Vector3d& c) {
                        return Eigen::Vector3d(sim::pier_displacement(sj, c, 1, cj.bending) -
                                               sim::pier_displacement(sj, c, 0, c0.bending));
                    });
                const Eigen::Vector3d e = d.along - truth;
                const Eigen::Vector3d& se = d.along_standard_error;
                h[j].add(e[1], se[1]);
                v[j].add(e[2], se[2]);
                std::printf(
                    "%4d %5.3f %+7.3f %+7.3f | %-8s %5zu | %+.3f ± %.3f    | %+.3f ± %.3f\n",
                    first_seed + s, pixels, shift[0], shift[1], segments.segments[z].zone.c_str(),
                    d.count, 1e3 * e[1], 1e3 * se[1], 1e3 * e[2], 1e3 * se[2]);
            }
        }
        std::fflush(stdout);
    }
    std::printf("\nper phase, over %d seeds and the zones: mean error (mm), RMS(error/SE)\n",
                seeds);
    std::printf("phase px |  h mean   h e/SE |  v mean   v e/SE\n");
    Sum all_h, all_v;
    for (int j = 0; j < phases; ++j) {
        std::printf("%8.3f | %+.3f  %6.2f | %+.3f  %6.2f\n", whole + double(j) / phases,
                    1e3 * h[j].e / h[j].n, std::sqrt(h[j].z2 / h[j].n), 1e3 * v[j].e / v[j].n,
                    std::sqrt(v[j].z2 / v[j].n));
        all_h.e += h[j].e, all_h.z2 += h[j].z2, all_h.n += h[j].n;
        all_v.e += v[j].e, all_v.z2 += v[j].z2, all_v.n += v[j].n;
    }
    std::printf("all      | %+.3f  %6.2f | %+.3f  %6.2f\n", 1e3 * all_h.e / all_h.n,
                std::sqrt(all_h.z2 / all_h.n), 1e3 * all_v.e / all_v.n,
                std::sqrt(all_v.z2 / all_v.n));
    std::printf("%.0f s wall, %.0f s CPU\n", bench::seconds_since(t0),
                bench::process_cpu_seconds());
    return 0;
}
