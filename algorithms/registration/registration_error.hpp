#pragma once
// How uncertain the registration makes a point: the transformation's covariance propagated
// to a location (Σ_p = J·Σ·Jᵀ), its σ along a surface normal (what M3C2's level of
// detection adds), and the worst of a zone's points.
#include <Eigen/Core>
#include <span>

#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration {

// Covariance (m², reference frame) of the transformed position of `epoch_point` (a point in
// the epoch's frame) due to the transformation's uncertainty alone.
Eigen::Matrix3d registration_covariance_at(const RigidTransform& T,
                                           const Eigen::Vector3d& epoch_point);

// σ (m) of that error along the unit vector `direction` (e.g. a core point's normal).
double registration_sigma_along(const RigidTransform& T, const Eigen::Vector3d& epoch_point,
                                const Eigen::Vector3d& direction);

struct ZoneRegistrationError {
    double max_sigma_3d = 0.0;      // m, max over points of √tr(Σ_p)
    double rms_sigma_3d = 0.0;      // m, RMS over points of √tr(Σ_p)
    double max_sigma_normal = 0.0;  // m, max over points of σ along its normal (0 without normals)
};

// Over a zone's points; `normals` is empty or one unit normal per point.
ZoneRegistrationError zone_registration_error(const RigidTransform& T,
                                              std::span<const Eigen::Vector3d> epoch_points,
                                              std::span<const Eigen::Vector3d> normals);

}  // namespace tlsmon::registration
