#pragma once
// The part of a simulated scan that holds the site's stable ground (simulator/stable_ground.hpp,
// the ICP's [[stable_region]] boxes): the scan's lower band, from its lowest row to the
// highest corner of a box, at a coarse step. Rendering only that keeps the ICP's tests and
// benches fast; the rows above (the pier, the deck) are never in a region.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "simulator/drift.hpp"
#include "simulator/render.hpp"
#include "simulator/stable_ground.hpp"

namespace tlsmon::test {

// The highest elevation (degrees, scanner frame) at which the scanner sees a corner of a box.
inline double highest_box_elevation_deg(const sim::Site& site,
                                        const std::vector<sim::StableBox>& boxes) {
    const Eigen::Affine3d to_scanner = sim::nominal_pose(site.scanner).inverse();
    double highest = site.scanner.elevation_min_deg;
    for (const auto& b : boxes) {
        const Eigen::AlignedBox3d box(b.min, b.max);
        for (int c = 0; c < 8; ++c) {
            const Eigen::Vector3d d =
                to_scanner * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
            highest = std::max(
                highest, std::atan2(d.z(), std::hypot(d.x(), d.y())) * 180.0 / std::numbers::pi);
        }
    }
    return highest;
}

// Epoch `c` of the site's overview (detail scans left out) up to `elevation_max_deg`, at
// `step_deg`.
inline sim::RenderedScan render_lower_band(sim::Site site, const sim::EpochConditions& c,
                                           double elevation_max_deg, double step_deg = 0.05) {
    site.scanner.details.clear();
    site.scanner.azimuth_step_deg = step_deg;
    site.scanner.elevation_step_deg = step_deg;
    site.scanner.elevation_max_deg = std::min(site.scanner.elevation_max_deg, elevation_max_deg);
    return sim::render_epoch(site, c, 2);
}

}  // namespace tlsmon::test
