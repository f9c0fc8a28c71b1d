#pragma once
// One epoch of a simulated site rendered in the scan's lower band that holds the stable
// ground (tests/support/stable_band.hpp), with the map of its header frame into the true
// frame: what the benches that score a registration on the ground over independent series
// (bench/icp_coverage.cpp, bench/stable_area_coverage.cpp) register and score against.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "tests/support/stable_band.hpp"

namespace tlsmon::bench {

struct Band {
    std::vector<Scan> scans;
    Eigen::Affine3d header_to_true = Eigen::Affine3d::Identity();
};

inline Band render_band(const sim::Site& site, int epoch, double hours, double elevation_max,
                        double step) {
    const sim::RenderedScan r = test::render_lower_band(
        site, sim::epoch_conditions(site, epoch, hours), elevation_max, step);
    const Eigen::Affine3d N = sim::nominal_pose(site.scanner);
    Band b;
    b.header_to_true = N * r.pose_error.transform() * N.inverse();
    b.scans.push_back(r.scan);
    return b;
}

// Series k of a run from `first_seed`: its own noise seed, a reference epoch and one later
// epoch 24·frac(0.618·(k + 1)) hours after it (the scanner's drift sweeps its day), and the
// exact map of the later epoch's header frame into the reference's, H₀⁻¹·H₁.
struct BandSeries {
    Band reference, epoch;
    Eigen::Affine3d exact() const {
        return reference.header_to_true.inverse() * epoch.header_to_true;
    }
};

inline BandSeries render_series(const sim::Site& base, int first_seed, int k, double elevation_max,
                                double step) {
    sim::Site site = base;
    site.noise.seed = static_cast<std::uint64_t>(first_seed + k);
    const double hours = 24.0 * std::fmod(0.6180339887 * (k + 1), 1.0);
    return {render_band(site, 0, 0.0, elevation_max, step),
            render_band(site, 1, hours, elevation_max, step)};
}

}  // namespace tlsmon::bench
