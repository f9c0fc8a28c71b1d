#include "algorithms/registration/registration_error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tlsmon::registration {

Eigen::Matrix3d registration_covariance_at(const RigidTransform& T,
                                           const Eigen::Vector3d& epoch_point) {
    // p_ref = s·exp([θ]×)·R·p + t, so ∂p_ref/∂(θ, t, s) = [ −s·[R·p]× | I | R·p ]
    // (first-order propagation, Niemeier 2008, §2.4: Σ_yy = F·Σ_xx·Fᵀ).
    const Eigen::Vector3d y = T.rotation * epoch_point;
    Eigen::Matrix<double, 3, 7> J = Eigen::Matrix<double, 3, 7>::Zero();
    const Eigen::Vector3d sy = T.scale * y;
    J.leftCols<3>() << 0, sy.z(), -sy.y(), -sy.z(), 0, sy.x(), sy.y(), -sy.x(), 0;
    J.block<3, 3>(0, 3).setIdentity();
    J.col(6) = y;  // the scale's rows of the covariance are zero when it is not estimated
    return J * T.small_rotation_covariance * J.transpose();
}

double registration_sigma_along(const RigidTransform& T, const Eigen::Vector3d& epoch_point,
                                const Eigen::Vector3d& direction) {
    const Eigen::Vector3d n = direction.normalized();
    return std::sqrt(std::max(0.0, n.dot(registration_covariance_at(T, epoch_point) * n)));
}

ZoneRegistrationError zone_registration_error(const RigidTransform& T,
                                              std::span<const Eigen::Vector3d> epoch_points,
                                              std::span<const Eigen::Vector3d> normals) {
    if (!normals.empty() && normals.size() != epoch_points.size())
        throw Error("zone registration error: " + std::to_string(normals.size()) + " normals for " +
                    std::to_string(epoch_points.size()) + " points");
    ZoneRegistrationError out;
    double sum2 = 0.0;
    for (std::size_t i = 0; i < epoch_points.size(); ++i) {
        const Eigen::Matrix3d S = registration_covariance_at(T, epoch_points[i]);
        const double s3 = std::sqrt(std::max(0.0, S.trace()));
        out.max_sigma_3d = std::max(out.max_sigma_3d, s3);
        sum2 += s3 * s3;
        if (!normals.empty()) {
            const Eigen::Vector3d n = normals[i].normalized();
            out.max_sigma_normal =
                std::max(out.max_sigma_normal, std::sqrt(std::max(0.0, n.dot(S * n))));
        }
    }
    if (!epoch_points.empty())
        out.rms_sigma_3d = std::sqrt(sum2 / static_cast<double>(epoch_points.size()));
    return out;
}

}  // namespace tlsmon::registration
