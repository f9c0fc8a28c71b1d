#pragma once
// The M3C2 normal at a core point (Lague 2013, step 1: the normal of the reference cloud at
// scale D around the core point; with several scales, the one where the cloud is most
// planar). Definitions, as pinned by tests/algorithms/test_m3c2_*.cpp and docs/m3c2.md:
// for each radius r_k, the points of the reference within distance <= r_k of the core point
// c; their covariance with the sample normalisation (n - 1); eigenvalues l0 <= l1 <= l2;
// planarity (l1 - l0) / l2. The normal is the eigenvector of l0 at the radius of highest
// planarity (the first such radius on ties). A radius with fewer than 3 points (or all of
// them at one place) is skipped; none left: the normal is undefined. Oriented so that
// n . v >= 0 for the orientation vector v.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "algorithms/m3c2/parameters.hpp"

namespace tlsmon::m3c2 {

struct CoreNormal {
    Eigen::Vector3d normal = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    double radius = std::numeric_limits<double>::quiet_NaN();  // the radius it was taken at
    bool defined() const { return normal.allFinite(); }
};

// `normal` flipped, if need be, so that normal . v >= 0 for the orientation's v at c.
Eigen::Vector3d oriented(const Eigen::Vector3d& normal, const Eigen::Vector3d& c,
                         const Orientation& orientation);

// At one core point from its neighbours: the indices into `cloud` of the points within the
// largest radius of c, in ascending order.
CoreNormal normal_at(const Eigen::Vector3d& c, const std::vector<Eigen::Vector3d>& cloud,
                     std::span<const std::uint32_t> neighbours, const NormalParameters& parameters);

// At every core point, parallel over core points; `left_out` as for cylinder_sides.
std::vector<CoreNormal> estimate_normals(const std::vector<Eigen::Vector3d>& cloud,
                                         const std::vector<Eigen::Vector3d>& core_points,
                                         const NormalParameters& parameters, unsigned threads = 0,
                                         std::span<const std::uint8_t> left_out = {});

}  // namespace tlsmon::m3c2
