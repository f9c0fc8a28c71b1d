#pragma once
// The rough slope on which PB-M3C2 and M3C2 are compared (tests/pipeline/
// test_pbm3c2_rough_slope.cpp, bench/rough_slope.cpp): the `pier` preset's valley side (20°,
// seen at 80 m, 74° off its normal) roughened (sim::Terrain::roughness), a patch of it
// settling 1 mm an epoch (sim::Creep), rendered in a window about that patch at 0.02°; both
// methods with their defaults on one zone, each epoch put into the reference's frame by the
// exact map, so that what is scored is the method, not the registration. Truth: the slab's
// displacement along each core point's or patch's normal.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pbm3c2_stage.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/simulator/narrow_window.hpp"
#include "tests/support/simulated_targets.hpp"

namespace tlsmon::test {

inline const Eigen::Vector3d kSlopeCreepCentre(-2.0, 80.0, 7.14);  // 7.1 m up the valley side

// ±roughness (m) at `wavelength` (m); the scanner still and the air unchanged.
inline sim::Site rough_slope(double roughness = 0.01, double wavelength = 0.25) {
    sim::Site site = sim::preset_pier();
    site.terrain.roughness = roughness;
    site.terrain.roughness_wavelength = wavelength;
    site.terrain.creep.from_epoch = 1;
    site.terrain.creep.centre = kSlopeCreepCentre.head<2>();
    site.terrain.creep.radius = 5.0;
    site.terrain.creep.rate = {0.0, 0.0, -0.001};
    site.drift.enabled = false;
    site.atmosphere.enabled = false;
    return site;
}

inline sim::EpochConditions slope_conditions(const sim::Site& site, int epoch) {
    return sim::epoch_conditions(site, epoch, 2.0 * epoch);
}

// The slope's window, ±`window`° about the creeping patch, at 0.02° (3 cm at 80 m).
inline std::vector<Scan> render_slope(const sim::Site& site, int epoch, double window) {
    sim::Site slope = site;
    slope.scanner.azimuth_step_deg = slope.scanner.elevation_step_deg = 0.02;
    sim::test::narrow_window(slope.scanner, kSlopeCreepCentre, window);
    return {sim::render_epoch(slope, slope_conditions(site, epoch), 2).scan};
}

// Errors against the truth and the LoD95 beside each.
struct SlopeScore {
    double sum = 0, sum2 = 0, lod = 0;
    std::size_t n = 0, within = 0;
    void add(double error, double lod95) {
        sum += error, sum2 += error * error, lod += lod95;
        ++n, within += std::abs(error) <= lod95;
    }
    void add(const SlopeScore& o) {
        sum += o.sum, sum2 += o.sum2, lod += o.lod;
        n += o.n, within += o.within;
    }
    double bias() const { return sum / double(n); }
    double rms() const { return std::sqrt(sum2 / double(n)); }
    double mean_lod() const { return lod / double(n); }
    double share_within() const { return double(within) / double(n); }
};

// M3C2 and PB-M3C2 over epochs 1..epochs of `site` against its epoch 0, the scan's window
// ±`window`° about the slope.
inline std::pair<SlopeScore, SlopeScore> score_slope(const sim::Site& site, int epochs,
                                                     double window) {
    const Eigen::Vector3d half(2.4, 2.4, 2.5);
    const ZoneShape zone = box_zone("slope", kSlopeCreepCentre - half, kSlopeCreepCentre + half);
    M3c2Config m3c2;
    m3c2.zones = {zone};
    PbM3c2Config pb;
    pb.zones = {zone};
    const auto e0 = render_slope(site, 0, window);
    const M3c2Reference m3c2_ref = prepare_m3c2_reference(m3c2, e0);
    const PbM3c2Reference pb_ref =
        prepare_pbm3c2_reference(pb, build_supervoxels(pb.segmentation, e0), e0);
    SlopeScore m, p;
    for (int i = 1; i <= epochs; ++i) {
        const auto ei = render_slope(site, i, window);
        const StageOutputs o =
            exact_outputs(site, slope_conditions(site, 0), slope_conditions(site, i), ei[0]);
        const Eigen::Vector3d u = site.terrain.creep.displacement(i);
        const M3c2Epoch me = measure_m3c2(m3c2, m3c2_ref, ei, o);
        for (auto k : m3c2_ref.zone_cores[0]) {
            const auto& d = me.distances[k];
            if (std::isfinite(d.distance))
                m.add(d.distance - u.dot(m3c2_ref.reference.normals()[k]), d.lod);
        }
        const PbM3c2Epoch pe = measure_pbm3c2(pb, pb_ref, ei, o);
        for (auto k : pb_ref.zone_patches[0]) {
            const auto& d = pe.results[k].distance;
            if (std::isfinite(d.distance))
                p.add(d.distance - u.dot(pb_ref.patches[k].frame.normal), d.lod);
        }
    }
    return {m, p};
}

}  // namespace tlsmon::test
