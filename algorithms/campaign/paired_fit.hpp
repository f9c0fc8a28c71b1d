#pragma once
// The rigid transformation that best maps points onto known counterparts along the
// counterparts' surface normals: the parameters p (segment_registration.hpp's, about c) that
// minimise Σ (nᵢ·(x'ᵢ(p) − qᵢ))². With the pairs known, it is what a point-to-plane fit would
// find without noise or search — the simulator's true transformation of a segment whose
// points are not moved rigidly (a personal scanner's drift changes along its walk), in the
// directions the segment's surfaces hold. Gauss–Newton; the directions whose information
// (rotations scaled by the points' RMS distance from c) is below `min_information` × the
// strongest stay at zero.
#include <Eigen/Core>
#include <span>

#include "algorithms/campaign/segment_registration.hpp"

namespace tlsmon::campaign {

Vector6 fit_pairs_point_to_plane(std::span<const Eigen::Vector3d> from,
                                 std::span<const Eigen::Vector3d> to,
                                 std::span<const Eigen::Vector3d> normals,
                                 const Eigen::Vector3d& centroid, double min_information = 1e-6);

}  // namespace tlsmon::campaign
