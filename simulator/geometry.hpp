#pragma once
// Ray intersections with the simple solids the scene is built from: axis-aligned boxes
// (slab method), spheres, finite cylinders with any axis. Rays are origin o + t·d, d unit;
// every function returns the nearest entry t > 0, or infinity for a miss.
#include <Eigen/Core>
#include <limits>

namespace tlsmon::sim {

constexpr double kNoHit = std::numeric_limits<double>::infinity();

struct BoxHit {
    double t = kNoHit;
    int axis = -1;     // 0 x, 1 y, 2 z
    bool low = false;  // entered through the low face of that axis
};

// Slab method (Kay & Kajiya 1986): entry distance into an axis-aligned box.
BoxHit intersect_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
                     const Eigen::Vector3d& d);

// The ray's parameter interval inside the box, clipped to (0, t_max]; false when empty.
// The cheap bounding test before any detailed intersection.
bool box_interval(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
                  const Eigen::Vector3d& d, double t_max, double& t_in, double& t_out);

// |o + t d − c|² = r²: the smaller positive root.
double intersect_sphere(const Eigen::Vector3d& c, double r, const Eigen::Vector3d& o,
                        const Eigen::Vector3d& d);

// Finite cylinder of radius r about the segment a–b, closed by flat caps. `normal` is set
// for a hit (outward, unit).
double intersect_cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                          const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                          Eigen::Vector3d& normal);

}  // namespace tlsmon::sim
