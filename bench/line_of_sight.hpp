#pragma once
// The axes a target's centre error is read in: along the scanner's line of sight, across it
// horizontally, and across it in the vertical plane (the rows of the returned matrix).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tlsmon::bench {

inline Eigen::Matrix3d sight_axes(const Eigen::Vector3d& line_of_sight) {
    const Eigen::Vector3d los = line_of_sight.normalized();
    const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(los).normalized();
    Eigen::Matrix3d a;
    a.row(0) = los;
    a.row(1) = across;
    a.row(2) = los.cross(across);
    return a;
}

}  // namespace tlsmon::bench
