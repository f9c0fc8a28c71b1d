#pragma once
// What the M3C2 stage needs of the site: the M3C2 parameters ([m3c2], docs/configuration.md)
// and the zones whose core points it aggregates.
#include <Eigen/Core>
#include <vector>

#include "algorithms/zones/zone_shape.hpp"

namespace tlsmon {

enum class M3c2Statistic { mean, median };

struct M3c2Config {
    bool enabled = true;                         // runs when there is at least one zone
    double core_spacing = 0.5;                   // m, cubes of the core point subsampling
    std::vector<double> normal_radii{0.5, 1.0};  // m, D/2 of Lague 2013
    double cylinder_radius = 0.5;                // m, d/2
    double max_depth = 1.0;                      // m, half-length h of the cylinder
    int min_points = 10;                         // per cylinder and cloud, else NaN
    bool orient_to_scanner = true;               // else along `orientation`
    Eigen::Vector3d orientation = Eigen::Vector3d::UnitZ();
    M3c2Statistic statistic = M3c2Statistic::mean;  // per cylinder: mean/std or median/IQR
    // m: a reference cylinder spread beyond this is an edge or clutter: no distance there
    double max_roughness = 0.02;
    double registration_error = 0.0;                // m, the LoD's reg without a registration
    int threads = 0;                                // 0: every core
    std::vector<ZoneShape> zones;
};

}  // namespace tlsmon
