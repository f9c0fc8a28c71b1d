// Patch-based M3C2 beside M3C2 on full `pier` epochs (10.5 M cells at 0.013°, 2 threads):
// the reference products once (for PB-M3C2 the supervoxels, then the patches in the zones),
// then per epoch each method's measurement and zone rows, timed; and both against the
// simulator's truth on the same zones (tests/support/simulated_zones.hpp, the defaults of
// [m3c2] and [pbm3c2]): per zone the bias, RMS and max of the zone median minus the true
// change along the normals (over the core points for M3C2, over the patches' footprint cells
// for PB-M3C2's median over the zone's area), the zone's median per-point LoD95, and the share of
// core points or patches with |d − truth| ≤ LoD95. Registration on the preset's targets with the
// truth's range scales (as from a weather station). Every place of an epoch shares its registration
// error, one draw of σ_T, so the patches are also scored with it taken out (the realized error
// from the simulator's pose errors) against the fits' own LoD95, 1.96·σ_fits, and each epoch's
// draw is printed in units of σ_T at the south face. No parameter was tuned on these epochs.
//
//   bench_pbm3c2_stage [EPOCHS] [FIRST]   epochs FIRST.. after the reference, 3 h apart
//                                          (default 2 from 1)
#include "pipeline/pbm3c2_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "bench/bench_support.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/registration_stage.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/support/pbm3c2_truth.hpp"
#include "tests/support/simulated_targets.hpp"
#include "tests/support/simulated_zones.hpp"

namespace {

using namespace tlsmon;
using bench::process_cpu_seconds;
using bench::seconds_since;

double median_of(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Score {
    double sum = 0, sum2 = 0, worst = 0;
    std::vector<double> point_lods;
    int n = 0;
    void add(double e) {
        sum += e, sum2 += e * e, worst = std::max(worst, std::abs(e));
        ++n;
    }
};

// One method's values at its measuring places: distance, LoD95, the true change, per zone;
// per zone the median and its truth where they are not the places' (PB-M3C2's, over the
// zone's area).
struct Places {
    std::vector<double> d, lod, truth;
    std::vector<std::vector<std::uint32_t>> zones;
    std::vector<double> zone_median, zone_truth;
};

void score(const char* method, const Places& p, const std::vector<std::string>& names,
           std::map<std::string, Score>& scores, std::size_t& valid, std::size_t& within) {
    for (std::size_t z = 0; z < names.size(); ++z) {
        std::vector<double> d, t, lod;
        std::size_t in = 0;
        for (auto k : p.zones[z]) {
            if (!std::isfinite(p.d[k])) continue;
            d.push_back(p.d[k]), t.push_back(p.truth[k]), lod.push_back(p.lod[k]);
            ++valid;
            in += std::abs(p.d[k] - p.truth[k]) <= p.lod[k];
        }
        within += in;
        const double value = p.zone_median.empty() ? median_of(d) : p.zone_median[z];
        const double truth = p.zone_truth.empty() ? median_of(t) : p.zone_truth[z];
        const double e = value - truth;
        std::printf(
            "  %-7s %-14s median %+.3f mm, truth %+.3f mm, error %+.3f mm, point LoD95 %.3f"
            " mm, n %zu, %.1f %% within\n",
            method, names[z].c_str(), 1e3 * value, 1e3 * truth, 1e3 * e, 1e3 * median_of(lod),
            d.size(), 100.0 * double(in) / double(d.size()));
        auto& s = scores[names[z]];
        s.add(e);
        s.point_lods.push_back(median_of(lod));
    }
}

}  // namespace

int main(int argc, char** argv) {
    const int epochs = argc > 1 ? std::atoi(argv[1]) : 2;
    const int first = argc > 2 ? std::atoi(argv[2]) : 1;
    const sim::Site site = sim::preset_pier();
    M3c2Config m3c2;
    m3c2.threads = 2;
    m3c2.zones = test::simulated_pier_zones(site);
    PbM3c2Config pb;
    pb.threads = 2;
    pb.zones = m3c2.zones;
    const RegistrationConfig targets = test::simulated_targets(site);

    auto t0 = std::chrono::steady_clock::now();
    const sim::EpochConditions c0 = sim::epoch_conditions(site, 0, 0.0);
    M3c2Reference m3c2_ref;
    PbM3c2Reference pb_ref;
    ReferenceTargets reference;
    {
        const std::vector<Scan> scans{sim::render_epoch(site, c0, 2).scan};
        std::printf("epoch 0 rendered: %zu points, %.1f s\n", scans[0].size(), seconds_since(t0));
        reference = measure_reference_targets(targets, scans);
        double cpu0 = process_cpu_seconds();
        t0 = std::chrono::steady_clock::now();
        m3c2_ref = prepare_m3c2_reference(m3c2, scans);
        std::printf("m3c2 reference product: %zu core points, %.2f s wall, %.2f s cpu\n",
                    m3c2_ref.reference.size(), seconds_since(t0), process_cpu_seconds() - cpu0);
        cpu0 = process_cpu_seconds();
        t0 = std::chrono::steady_clock::now();
        const ReferenceSupervoxels sv = build_supervoxels(pb.segmentation, scans);
        std::printf("supervoxels: %zu, %.2f s wall, %.2f s cpu\n", sv.patches.size(),
                    seconds_since(t0), process_cpu_seconds() - cpu0);
        cpu0 = process_cpu_seconds();
        t0 = std::chrono::steady_clock::now();
        pb_ref = prepare_pbm3c2_reference(pb, sv, scans);
        std::printf("pbm3c2 reference product: %zu patches, %.2f s wall, %.2f s cpu, %zu bytes\n",
                    pb_ref.patches.size(), seconds_since(t0), process_cpu_seconds() - cpu0,
                    pb_ref.encode().size());
    }
    std::map<std::string, Score> m3c2_scores, pb_scores;
    std::size_t m3c2_valid = 0, m3c2_within = 0, pb_valid = 0, pb_within = 0, pb_own_within = 0,
                pb_measured = 0;
    for (int i = first; i < first + epochs; ++i) {
        const double hours = 3.0 * i;
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
        const auto truth_at = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& n) {
            return (sim::pier_displacement(site, c, i, ci.bending) -
                    sim::pier_displacement(site, c, 0, c0.bending))
                .dot(n);
        };

        t0 = std::chrono::steady_clock::now();
        double cpu0 = process_cpu_seconds();
        const M3c2Epoch m = measure_m3c2(m3c2, m3c2_ref, scans, o);
        m3c2_zone_results(m3c2, m3c2_ref, m);
        std::printf("epoch %d: m3c2 %.2f s wall, %.2f s cpu", i, seconds_since(t0),
                    process_cpu_seconds() - cpu0);
        t0 = std::chrono::steady_clock::now();
        cpu0 = process_cpu_seconds();
        const PbM3c2Epoch p = measure_pbm3c2(pb, pb_ref, scans, o);
        const auto pb_rows = pbm3c2_zone_results(pb_ref, p);
        std::printf("; pbm3c2 %.2f s wall, %.2f s cpu\n", seconds_since(t0),
                    process_cpu_seconds() - cpu0);

        Places mp, pp;
        for (std::size_t k = 0; k < m3c2_ref.reference.size(); ++k) {
            const auto& n = m3c2_ref.reference.normals()[k];
            mp.d.push_back(m.distances[k].distance);
            mp.lod.push_back(m.distances[k].lod);
            mp.truth.push_back(n.allFinite() ? truth_at(m3c2_ref.reference.core_points()[k], n)
                                             : std::nan(""));
        }
        mp.zones = m3c2_ref.zone_cores;
        double draw = std::nan("");  // at the south face's first measured patch, in σ_T
        for (std::size_t k = 0; k < pb_ref.patches.size(); ++k) {
            const auto& f = pb_ref.patches[k].frame;
            const auto& r = p.results[k].distance;
            pp.d.push_back(r.distance);
            pp.lod.push_back(r.lod);
            pp.truth.push_back(truth_at(pb_ref.measured_at(k, &p.results[k]), f.normal));
            if (!std::isfinite(r.distance)) continue;
            const double e = test::registration_error_at(site, c0, ci, *o.to_reference,
                                                         pb_ref.measured_at(k, &p.results[k]))
                                 .dot(f.normal);
            ++pb_measured;
            pb_own_within += std::abs(r.distance - pp.truth.back() - e) <= 1.96 * r.sampling_sigma;
            if (std::isnan(draw) && pb_ref.zone_names[0] == "south" &&
                std::count(pb_ref.zone_patches[0].begin(), pb_ref.zone_patches[0].end(), k))
                draw = e / p.registration_sigma[k];
        }
        std::printf("epoch %d: the registration's realized error at the south face %+.2f σ_T\n", i,
                    draw);
        pp.zones = pb_ref.zone_patches;
        for (std::size_t z = 0; z < pb_ref.zone_names.size(); ++z) {
            pp.zone_median.push_back(std::nan(""));
            for (const auto& row : pb_rows)
                if (row.zone == pb_ref.zone_names[z] && row.quantity == "pbm3c2_median_m")
                    pp.zone_median.back() = row.value;
            pp.zone_truth.push_back(
                test::areal_median_truth(pb_ref, p, z, [&](const Eigen::Vector3d& x) {
                    return Eigen::Vector3d(sim::pier_displacement(site, x, i, ci.bending) -
                                           sim::pier_displacement(site, x, 0, c0.bending));
                }));
        }
        score("m3c2", mp, m3c2_ref.zone_names, m3c2_scores, m3c2_valid, m3c2_within);
        score("pbm3c2", pp, pb_ref.zone_names, pb_scores, pb_valid, pb_within);
    }
    std::printf(
        "per zone over the epochs (mm): zone median error bias, RMS, max; median point"
        " LoD95\n");
    for (const auto& [zone, s] : m3c2_scores) {
        const auto& q = pb_scores[zone];
        std::printf(
            "  %-14s m3c2 %+.3f %.3f %.3f LoD %.3f | pbm3c2 %+.3f %.3f %.3f LoD %.3f"
            " (%.0f %% smaller)\n",
            zone.c_str(), 1e3 * s.sum / s.n, 1e3 * std::sqrt(s.sum2 / s.n), 1e3 * s.worst,
            1e3 * median_of(s.point_lods), 1e3 * q.sum / q.n, 1e3 * std::sqrt(q.sum2 / q.n),
            1e3 * q.worst, 1e3 * median_of(q.point_lods),
            100.0 * (1.0 - median_of(q.point_lods) / median_of(s.point_lods)));
    }
    std::printf(
        "within LoD95: m3c2 %zu of %zu core points (%.1f %%), pbm3c2 %zu of %zu patches"
        " (%.1f %%)\n",
        m3c2_within, m3c2_valid, 100.0 * double(m3c2_within) / double(m3c2_valid), pb_within,
        pb_valid, 100.0 * double(pb_within) / double(pb_valid));
    std::printf(
        "the registration's realized error taken out: pbm3c2 %zu of %zu patches within the fits'"
        " own LoD95 (%.1f %%)\n",
        pb_own_within, pb_measured, 100.0 * double(pb_own_within) / double(pb_measured));
    return 0;
}
