#pragma once
// A plane adjusted to a group of points (orthogonal regression through the centroid, the
// normal the eigenvector of the scatter matrix's smallest eigenvalue), with the covariance of
// its normal and of the centroid's position along it: what the plane-based registration
// (plane_registration.hpp) takes as an observation.
//
// With M = Σ (pᵢ − c)(pᵢ − c)ᵀ = Σ λ_k·e_k·e_kᵀ (λ1 ≥ λ2 ≥ λ3, e3 = n) and σ the points'
// standard deviation along the normal, the normal tilts towards e_k (k = 1, 2) with variance
// σ²/λ_k and the centroid's offset along n has variance σ²/N, independent of the tilt
// (Weingarten, Gruener & Siegwart 2004, "Probabilistic plane fitting in 3D and an application
// to robotic mapping", eqs. 9–13; the Hessian of the orthogonal-regression objective):
//
//   Σ_n = σ²·(e1·e1ᵀ/λ1 + e2·e2ᵀ/λ2),   σ²_c = σ²/N,   s² = λ3/(N − 3)
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>

namespace tlsmon::registration {

struct FittedPlane {
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit; n·x = n·centroid on the plane
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Matrix3d normal_covariance = Eigen::Matrix3d::Zero();  // rank 2, tangent to the sphere
    double centroid_variance = 0.0;  // m², of the centroid along the normal
    double point_sigma = 0.0;        // σ used for the covariance, m
    double residual_sigma = 0.0;     // s = √(λ3/(N − 3)): the points' own scatter about it, m
    std::size_t points = 0;
    // The in-plane axes e1 (longest extent), e2 and their spread: λ1, λ2 as RMS extents, m.
    Eigen::Vector3d axis_long = Eigen::Vector3d::UnitX(), axis_short = Eigen::Vector3d::UnitY();
    double extent_long = 0.0, extent_short = 0.0;

    double distance() const { return normal.dot(centroid); }  // Hesse form n·x = d
};

// The plane through ≥ 3 points not on a line, its normal turned towards `viewpoint` (the
// scanner, at the origin of its own frame: the sign convention of M3C2's `orient = scanner`).
// `point_sigma` > 0: the scanner's σ of a point along the normal (the a-priori model); 0: the
// points' own scatter s (floored at 1e-6 m). Throws tlsmon::Error for fewer than 3 points or
// points on a line.
FittedPlane fit_plane(std::span<const Eigen::Vector3d> points, double point_sigma = 0.0,
                      const Eigen::Vector3d& viewpoint = Eigen::Vector3d::Zero());
// The same for the points `indices` of `cloud`, without copying them (a plane of millions).
FittedPlane fit_plane(std::span<const Eigen::Vector3d> cloud,
                      std::span<const std::uint32_t> indices, double point_sigma = 0.0,
                      const Eigen::Vector3d& viewpoint = Eigen::Vector3d::Zero());

}  // namespace tlsmon::registration
