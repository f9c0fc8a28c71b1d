// The 3-D vectors stage on full `pier` epochs (10.5 M cells at 0.013°, 2 threads): the
// reference product once (the supervoxels, then the areas in the zones with their samples),
// then per epoch the measurement (gathering the epoch's points per area, each area's
// registration) and the zone rows, timed, with the areas' outcomes. The zones are those
// `tlsmon simulate` writes (tests/support/simulated_zones.hpp), the parameters [vectors]'
// defaults; registration on the preset's targets with the truth's range scales.
//
//   bench_vectors_stage [EPOCHS] [FIRST]   epochs FIRST.. after the reference, 3 h apart
//                                           (default 2 from 1)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "bench/bench_support.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/vector_stage.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/simulated_zones.hpp"

int main(int argc, char** argv) {
    using namespace tlsmon;
    using bench::process_cpu_seconds;
    using bench::seconds_since;
    const int epochs = argc > 1 ? std::atoi(argv[1]) : 2;
    const int first = argc > 2 ? std::atoi(argv[2]) : 1;
    const sim::Site site = sim::preset_pier();
    VectorConfig config;
    config.threads = 2;
    config.zones = test::simulated_pier_zones(site);
    const RegistrationConfig targets = test::simulated_targets(site);

    auto t0 = std::chrono::steady_clock::now();
    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    const std::vector<Scan> scans0{sim::render_epoch(site, c0, 2).scan};
    std::printf("epoch 0 rendered: %zu points, %.1f s\n", scans0[0].size(), seconds_since(t0));
    const ReferenceTargets reference = measure_reference_targets(targets, scans0);
    double cpu0 = process_cpu_seconds();
    t0 = std::chrono::steady_clock::now();
    const ReferenceSupervoxels sv = build_supervoxels(config.segmentation, scans0);
    std::printf("supervoxels: %zu, %.2f s wall, %.2f s cpu\n", sv.patches.size(), seconds_since(t0),
                process_cpu_seconds() - cpu0);
    cpu0 = process_cpu_seconds();
    t0 = std::chrono::steady_clock::now();
    const VectorReference ref = prepare_vector_reference(config, sv, scans0);
    std::printf(
        "vectors reference product: %zu areas, %zu samples, %.2f s wall, %.2f s cpu, "
        "%zu bytes\n",
        ref.areas(), ref.samples.size(), seconds_since(t0), process_cpu_seconds() - cpu0,
        ref.encode().size());

    for (int e = first; e < first + epochs; ++e) {
        const double hours = 3.0 * e;
        const sim::EpochConditions c = sim::epoch_conditions(site, e, hours);
        t0 = std::chrono::steady_clock::now();
        const std::vector<Scan> scans{sim::render_epoch(site, c, 2).scan};
        std::printf("epoch %d (%.0f h) rendered: %.1f s\n", e, hours, seconds_since(t0));
        std::string refused;
        const auto outputs =
            test::simulated_outputs(targets, reference, scans, c.atmosphere.range_scale,
                                    c0.atmosphere.range_scale, refused);
        if (!outputs) {
            std::printf("  registration refused: %s\n", refused.c_str());
            continue;
        }
        cpu0 = process_cpu_seconds();
        t0 = std::chrono::steady_clock::now();
        const VectorEpoch v = measure_vectors(config, ref, scans, *outputs);
        const auto rows = vector_zone_results(config, ref, v);
        std::printf("  vectors: %.2f s wall, %.2f s cpu (%zu zone rows)\n", seconds_since(t0),
                    process_cpu_seconds() - cpu0, rows.size());
        std::map<std::string, int> outcomes;
        double iterations = 0;
        for (const auto& a : v.areas) {
            ++outcomes[vectors::outcome_name(a.fit.outcome)];
            iterations += a.fit.iterations;
        }
        std::printf("    Gauss-Newton iterations per area: %.1f\n",
                    iterations / double(v.areas.size()));
        for (const auto& [name, n] : outcomes) std::printf("    %s: %d\n", name.c_str(), n);
    }
    return 0;
}
