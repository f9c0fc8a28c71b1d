#pragma once
// Reference targets placed as a surveyor sets them out: by kind, horizontal distance (or
// slant range) and azimuth from the station, height above what they stand on, and mount.
// The supports are scene geometry (rays hit them and they can hide part of a target's
// surroundings):
//   mast      a vertical tube (radius 25 mm) from the ground up into the sphere, or behind
//             the centre of a checkerboard;
//   stand     a tripod: a centre pole (radius 20 mm) as the mast, and three legs (15 mm) from
//             60 % of its height to the ground 0.45·height out, at 90°, 210° and 330° from
//             the board's facing direction;
//   abutment  a short mast standing on the top of a stable block (foundation, abutment);
//   none      nothing modelled (a bracket on a wall).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct TargetPlacement {
    std::string name;
    Target::Kind kind = Target::Kind::sphere;
    double distance = 0.0;      // horizontal, from the scanner, m (used when range is 0)
    double range = 0.0;         // slant range to the centre, m; 0: use distance
    double azimuth_deg = 90.0;  // scanner frame, counter-clockwise from the scanner's +x
    double height = 1.5;        // centre above the ground or block top, m
    Target::Mount mount = Target::Mount::mast;
    double radius = 0.0725;  // sphere, m
    double size = 0.40;      // checkerboard side, m
};

// The target at that place, its centre's z from the terrain (or the block under it).
// Throws tlsmon::Error naming the target when `abutment` has no block under it, or the
// range is shorter than the height difference.
Target place_target(const Site& site, const TargetPlacement& p);

// The support's foot height for a target at its centre (terrain or block top); throws as
// above for an abutment mount with no block under it.
double target_base_z(const Site& site, const Target& t);

struct Cylinder {
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
    double radius = 0.0;
};

constexpr double kMastRadius = 0.025, kStandPoleRadius = 0.020, kStandLegRadius = 0.015;
constexpr double kBoardPoleOffset = 0.03;  // m behind a checkerboard

// The support's cylinders for the target with centre `centre` (it may have been knocked)
// and, for a checkerboard, facing `normal` (horizontal, towards the station).
std::vector<Cylinder> target_supports(const Target& t, const Eigen::Vector3d& centre,
                                      const Eigen::Vector3d& normal);

const char* mount_name(Target::Mount m);

}  // namespace tlsmon::sim
