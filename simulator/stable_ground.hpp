#pragma once
// The parts of a simulated site that never move, as boxes for the registration's ICP on
// stable regions ([[stable_region]] of docs/configuration.md): the ground and the foundation
// block around the pier's foot, each abutment with the ground beside it, and the valley's
// sloping sides (far ground that holds the rotations). Never the pier: every box keeps `gap`
// clear of the pier's footprint, and stops `headroom` above its block, below the boards and
// spheres mounted there; a slope's box ends `headroom` above the slope's highest point, far
// below the deck.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct StableBox {
    std::string name;
    Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
};

struct StableGroundLayout {
    double margin = 3.0;       // m of ground beyond a block's footprint
    double wall_margin = 0.5;  // m beyond a wall's (walls stand near the pier)
    double gap = 0.2;          // m kept clear of the pier's faces
    double headroom = 0.15;    // m above the block's top
    bool valley_sides = true;
    double valley_width = 100.0;  // m either side of the pier along x
};

std::vector<StableBox> stable_ground(const Site& site, const StableGroundLayout& layout = {});

}  // namespace tlsmon::sim
