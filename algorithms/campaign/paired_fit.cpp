#include "algorithms/campaign/paired_fit.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "algorithms/registration/so3.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {

Vector6 fit_pairs_point_to_plane(std::span<const Eigen::Vector3d> from,
                                 std::span<const Eigen::Vector3d> to,
                                 std::span<const Eigen::Vector3d> normals, const Eigen::Vector3d& c,
                                 double min_information) {
    if (from.size() != to.size() || from.size() != normals.size())
        throw Error("paired fit: points, counterparts and normals differ in number");
    if (from.empty()) return Vector6::Zero();
    double L2 = 0;
    for (const auto& x : from) L2 += (x - c).squaredNorm();
    const double L = std::max(std::sqrt(L2 / double(from.size())), 1e-9);
    Vector6 D;  // the rotations in metres at the points' RMS distance
    D << L, L, L, 1, 1, 1;
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    for (int iteration = 0; iteration < 10; ++iteration) {
        Matrix6 N = Matrix6::Zero();
        Vector6 b = Vector6::Zero();
        for (std::size_t i = 0; i < from.size(); ++i) {
            const Eigen::Vector3d y = R * (from[i] - c);
            Vector6 a;  // ∂(n·x')/∂(δθ, δt), left perturbation: δθ·(y × n) + δt·n
            a << y.cross(normals[i]), normals[i];
            a = a.cwiseQuotient(D);
            N += a * a.transpose();
            b -= a * normals[i].dot(y + c + t - to[i]);
        }
        const Eigen::SelfAdjointEigenSolver<Matrix6> eig(N);
        Vector6 step = Vector6::Zero();
        for (int j = 0; j < 6; ++j)
            if (eig.eigenvalues()(j) > min_information * eig.eigenvalues()(5))
                step += eig.eigenvectors().col(j) *
                        (eig.eigenvectors().col(j).dot(b) / eig.eigenvalues()(j));
        step = step.cwiseQuotient(D);
        R = registration::exp_so3(step.head<3>()) * R;
        t += step.tail<3>();
        if (step.head<3>().norm() * L + step.tail<3>().norm() < 1e-12) break;
    }
    Vector6 p;
    p << registration::log_so3(R), t;
    return p;
}

}  // namespace tlsmon::campaign
