#pragma once
// The truth written beside each simulated scan: everything needed to score registration,
// M3C2 and keypoint displacements exactly (see docs/simulator.md for every field).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "simulator/deformation.hpp"
#include "simulator/render.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

// A named material point of the pier where the truth reports the displacement vector.
struct SamplePoint {
    std::string name;
    Eigen::Vector3d point;  // undeformed position, project frame
};

// South face (head-on) and west face (grazing) at 5, 10, 20, 30 m and near the top, plus
// the centre of the top.
std::vector<SamplePoint> sample_points(const Site& site);

// The pier's axis at an epoch as a straight line: the least-squares line through the
// displaced centre line over the pier's height (a rigid tilt exactly; thermal bending's
// curved axis by its mean lean), and the centre of the top's displacement.
struct PierAxis {
    Eigen::Vector2d tilt = Eigen::Vector2d::Zero();  // rad, lean towards +x and +y
    Eigen::Vector3d top = Eigen::Vector3d::Zero();   // m
};
PierAxis pier_axis(const Site& site, int epoch, const ThermalBending& bending);

// `rendered` is null for a missing scan (pose error and grid then not reported).
nlohmann::json truth_json(const Site& site, int epoch, double hours, std::int64_t acquired_utc,
                          const RenderedScan* rendered);

// One detail scan's entry in the truth's scan.details: its window, step and grid.
nlohmann::json detail_truth(const DetailScan& d, const RenderedScan& rendered);

}  // namespace tlsmon::sim
