// The M3C2 stage on full `pier` epochs (10.5 M cells at 0.013°, 2 threads): the reference
// product once (core points in the zones, normals, the reference's side), then per epoch
// the pulled-back cylinders, the epoch's side, the LoD's registration term and the zone
// rows; and the accuracy against the simulator's truth, per zone (bias, RMS, max of the
// zone median minus the true change along the normals) and the share of core points with
// |d − truth| <= LoD95. Zones: tests/support/simulated_zones.hpp (the whole south face,
// seen head-on, and its 10 m bands, the west face, grazing, with their design normals); the
// [m3c2] defaults. Registration on the preset's
// targets with the truth's range scales (as from a weather station).
//
//   bench_m3c2_stage [EPOCHS]   epochs after the reference, 3 h apart (default 2)
#include "pipeline/m3c2_stage.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/simulated_zones.hpp"

namespace {

using namespace tlsmon;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

long peak_mb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss / 1024;
}

struct Score {
    double sum = 0, sum2 = 0, worst = 0;
    int n = 0;
};

}  // namespace

int main(int argc, char** argv) {
    const int epochs = argc > 1 ? std::atoi(argv[1]) : 2;
    const sim::Site site = sim::preset_pier();
    M3c2Config config;
    config.threads = 2;
    config.zones = test::simulated_pier_zones(site);
    const RegistrationConfig targets = test::simulated_targets(site);

    auto t0 = std::chrono::steady_clock::now();
    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    M3c2Reference ref;
    ReferenceTargets reference;
    {
        const std::vector<Scan> scans{sim::render_epoch(site, c0, 2).scan};
        std::printf("epoch 0 rendered: %zu points, %.1f s\n", scans[0].size(), seconds_since(t0));
        reference = measure_reference_targets(targets, scans);
        t0 = std::chrono::steady_clock::now();
        const double cpu0 = cpu_seconds();
        ref = prepare_m3c2_reference(config, scans);
        std::printf("reference product: cpu %.2f s\n", cpu_seconds() - cpu0);
        std::printf("reference product: %zu core points, %.2f s, %zu bytes encoded\n",
                    ref.reference.size(), seconds_since(t0), ref.encode().size());
    }
    std::map<std::string, Score> scores;
    std::size_t valid = 0, within = 0;
    for (int i = 1; i <= epochs; ++i) {
        const double hours = 3.0 * i;
        const sim::EpochConditions ci = sim::epoch_conditions(site, i, hours);
        t0 = std::chrono::steady_clock::now();
        const std::vector<Scan> scans{sim::render_epoch(site, ci, 2).scan};
        std::printf("epoch %d rendered: %zu points, %.1f s\n", i, scans[0].size(),
                    seconds_since(t0));
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
        const double cpu0 = cpu_seconds();
        const M3c2Epoch m = measure_m3c2(config, ref, scans, o);
        const auto rows = m3c2_zone_results(config, ref, m);
        const auto arrays = m3c2_core_point_arrays(ref, m);
        std::printf(
            "epoch %d: m3c2 stage %.2f s wall, %.2f s cpu (2 threads), peak RSS so far "
            "%ld MB\n",
            i, seconds_since(t0), cpu_seconds() - cpu0, peak_mb());
        std::vector<double> truth(ref.reference.size(), std::nan(""));
        for (std::size_t k = 0; k < truth.size(); ++k) {
            const auto& n = ref.reference.normals()[k];
            if (!n.allFinite()) continue;
            const auto& c = ref.reference.core_points()[k];
            truth[k] = (sim::pier_displacement(site, c, i, ci.bending) -
                        sim::pier_displacement(site, c, 0, c0.bending))
                           .dot(n);
            const auto& d = m.distances[k];
            if (!std::isfinite(d.distance)) continue;
            ++valid;
            within += std::abs(d.distance - truth[k]) <= d.lod;
        }
        for (const auto& row : rows) {
            if (row.quantity != "m3c2_median_m") continue;
            const auto z = std::find(ref.zone_names.begin(), ref.zone_names.end(), row.zone) -
                           ref.zone_names.begin();
            std::vector<double> v;
            for (auto k : ref.zone_cores[z]) {
                if (std::isfinite(m.distances[k].distance)) v.push_back(truth[k]);
            }
            std::sort(v.begin(), v.end());
            const double t =
                v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
            const double e = row.value - t;
            std::printf(
                "  %-14s median %+.3f mm, truth %+.3f mm, error %+.3f mm, LoD95 %.3f mm, n %lld\n",
                row.zone.c_str(), 1e3 * row.value, 1e3 * t, 1e3 * e,
                1e3 * row.uncertainty.value_or(0), static_cast<long long>(row.n));
            auto& s = scores[row.zone];
            s.sum += e;
            s.sum2 += e * e;
            s.worst = std::max(s.worst, std::abs(e));
            ++s.n;
        }
    }
    std::printf("per zone over %d epochs (mm): bias, RMS, max\n", epochs);
    for (const auto& [zone, s] : scores) {
        std::printf("  %-14s %+.3f %.3f %.3f\n", zone.c_str(), 1e3 * s.sum / s.n,
                    1e3 * std::sqrt(s.sum2 / s.n), 1e3 * s.worst);
    }
    std::printf("core points with |d - truth| <= LoD95: %zu of %zu (%.1f %%); peak RSS %ld MB\n",
                within, valid, 100.0 * double(within) / double(valid), peak_mb());
    return 0;
}
