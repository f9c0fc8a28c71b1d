#pragma once
// Small rotations as the adjustments linearise them: R̂ = exp([θ]×)·R, so that
// ∂(R̂·y)/∂θ = −[R·y]× at θ = 0.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tlsmon::registration {

// [a]×: the matrix of the cross product a × ·.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
    Eigen::Matrix3d S;
    S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return S;
}

// exp([θ]×): the rotation by |θ| about θ/|θ| (Rodrigues).
inline Eigen::Matrix3d exp_so3(const Eigen::Vector3d& theta) {
    const double angle = theta.norm();
    if (angle < 1e-300) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(angle, theta / angle).toRotationMatrix();
}

// log of a rotation: the rotation vector θ with exp([θ]×) = R.
inline Eigen::Vector3d log_so3(const Eigen::Matrix3d& rotation) {
    const Eigen::AngleAxisd aa(rotation);
    return aa.angle() * aa.axis();
}

}  // namespace tlsmon::registration
