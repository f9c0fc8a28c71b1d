// The primitives stage on full `round` epochs (the 4 m column at 47 m, 11.3 M cells at
// 0.013°, 2 threads): the reference product once (RANSAC on the thinned sample, the fine
// fit on every point of the zone), then per epoch the measurement and zone rows, timed; and
// against the simulator's truth: the lean's error (measured change − the tilt event's), its
// σ, and the part of it the target registration's rotation error makes (from the simulator's
// pose errors). The column tilts `TILT` arc seconds north-east from epoch 1 on (default 20);
// no thermal bending. Registration on the preset's targets with the truth's range scales.
// No parameter was tuned on these epochs.
//
//   bench_primitives_stage [EPOCHS] [TILT]   epochs 1..EPOCHS, 15 min apart (default 3)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "bench/bench_support.hpp"
#include "pipeline/primitive_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/support/simulated_targets.hpp"

namespace {

using namespace tlsmon;
using bench::process_cpu_seconds;
using bench::seconds_since;

constexpr double kArcsec = std::numbers::pi / (180.0 * 3600.0);

}  // namespace

int main(int argc, char** argv) {
    const int epochs = argc > 1 ? std::atoi(argv[1]) : 3;
    const double tilt = argc > 2 ? std::atof(argv[2]) : 20.0;
    sim::Site site = sim::preset_round();
    site.deformation.enabled = false;
    site.events.tilt_epoch = 1;
    site.events.tilt_arcsec = {tilt * std::cos(0.5), tilt * std::sin(0.5)};
    PrimitivesConfig config;
    config.threads = 2;
    const Eigen::Vector2d c = site.pier.centre();
    const double half = 0.5 * site.pier.diameter + 0.3;
    config.zones = {{box_zone("column", {c.x() - half, c.y() - half, 1.0},
                              {c.x() + half, c.y() + half, site.pier.height - 0.5}),
                     primitives::Kind::cylinder}};
    const RegistrationConfig targets = test::simulated_targets(site);

    auto t0 = std::chrono::steady_clock::now();
    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    PrimitiveReference ref;
    ReferenceTargets reference;
    {
        const std::vector<Scan> scans{sim::render_epoch(site, c0, 2).scan};
        std::printf("epoch 0 rendered: %zu points, %.1f s\n", scans[0].size(), seconds_since(t0));
        reference = measure_reference_targets(targets, scans);
        const double cpu0 = process_cpu_seconds();
        t0 = std::chrono::steady_clock::now();
        ref = prepare_primitives_reference(config, scans);
        const auto& e = ref.entries[0];
        std::printf(
            "reference product: %s, RANSAC %llu sample inliers, fit on %zu points "
            "(s0 %.2f, rms %.2f mm), radius %.4f m; %.2f s wall, %.2f s cpu\n",
            e.refused.empty() ? "cylinder" : e.refused.c_str(),
            static_cast<unsigned long long>(e.seed_inliers), e.fit.used, e.fit.s0, 1e3 * e.fit.rms,
            e.fit.primitive.radius(), seconds_since(t0), process_cpu_seconds() - cpu0);
    }
    for (int i = 1; i <= epochs; ++i) {
        const double hours = 0.25 * i;
        const sim::EpochConditions ci = sim::epoch_conditions(site, i, hours);
        const std::vector<Scan> scans{sim::render_epoch(site, ci, 2).scan};
        std::string refused;
        const auto registered =
            test::simulated_outputs(targets, reference, scans, ci.atmosphere.range_scale,
                                    c0.atmosphere.range_scale, refused);
        if (!registered) {
            std::printf("epoch %d: registration refused: %s\n", i, refused.c_str());
            continue;
        }
        const StageOutputs& o = *registered;
        t0 = std::chrono::steady_clock::now();
        const double cpu0 = process_cpu_seconds();
        const PrimitiveEpoch m = measure_primitives(config, ref, scans, o);
        const auto rows = primitive_zone_results(config, ref, m);
        const double wall = seconds_since(t0), cpu = process_cpu_seconds() - cpu0;
        if (m.fits[0].status != primitives::FitStatus::fitted) {
            std::printf("epoch %d: %s\n", i, primitives::to_string(m.fits[0].status));
            continue;
        }
        const Eigen::Vector2d truth = sim::pier_tilt(site, i);
        const Eigen::Vector2d error = m.changes[0].delta.segment<2>(2) - truth;
        const Eigen::Matrix3d dR =
            o.to_reference->rotation * test::exact_epoch_map(site, c0, ci).linear().transpose();
        double tilt_value = 0, tilt_lod = 0;
        for (const auto& row : rows)
            if (row.quantity == "cylinder_tilt_arcsec")
                tilt_value = row.value, tilt_lod = *row.uncertainty;
        std::printf(
            "epoch %d: %.2f s wall, %.2f s cpu, %zu points; tilt %.2f″ (truth %.2f″, LoD "
            "%.2f″); lean error (%+.2f, %+.2f)″, σ (%.2f, %.2f)″, of which the "
            "registration's (%+.2f, %+.2f)″\n",
            i, wall, cpu, m.fits[0].used, tilt_value, truth.norm() / kArcsec, tilt_lod,
            error.x() / kArcsec, error.y() / kArcsec,
            std::sqrt(m.changes[0].covariance(2, 2)) / kArcsec,
            std::sqrt(m.changes[0].covariance(3, 3)) / kArcsec, dR(0, 2) / kArcsec,
            -dR(2, 1) / kArcsec);
    }
    return 0;
}
