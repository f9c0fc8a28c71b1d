#include "algorithms/registration/plane_fit.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tlsmon::registration {

namespace {

// The fit over the n points point(0) … point(n − 1).
template <class Point>
FittedPlane fit(std::size_t n, Point point, double point_sigma, const Eigen::Vector3d& viewpoint) {
    if (n < 3) throw Error("plane fit: " + std::to_string(n) + " points, at least 3 needed");
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) c += point(i);
    c /= double(n);
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d q = point(i) - c;
        M.noalias() += q * q.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);  // ascending eigenvalues
    const Eigen::Vector3d lambda = eig.eigenvalues().cwiseMax(0.0);
    if (!(lambda(1) > 1e-12 * lambda(2)))  // middle vs largest: a line, or one point
        throw Error("plane fit: the points lie on a line");

    FittedPlane f;
    f.points = n;
    f.centroid = c;
    f.normal = eig.eigenvectors().col(0).normalized();
    if (f.normal.dot(viewpoint - c) < 0.0) f.normal = -f.normal;
    f.axis_short = eig.eigenvectors().col(1).normalized();
    f.axis_long = eig.eigenvectors().col(2).normalized();
    f.extent_long = std::sqrt(lambda(2) / double(n));
    f.extent_short = std::sqrt(lambda(1) / double(n));
    f.residual_sigma = n > 3 ? std::sqrt(lambda(0) / double(n - 3)) : 0.0;
    f.point_sigma = point_sigma > 0.0 ? point_sigma : std::max(f.residual_sigma, 1e-6);
    const double s2 = f.point_sigma * f.point_sigma;
    f.normal_covariance = s2 * (f.axis_long * f.axis_long.transpose() / lambda(2) +
                                f.axis_short * f.axis_short.transpose() / lambda(1));
    f.centroid_variance = s2 / double(n);
    return f;
}

}  // namespace

FittedPlane fit_plane(std::span<const Eigen::Vector3d> points, double point_sigma,
                      const Eigen::Vector3d& viewpoint) {
    return fit(
        points.size(), [&](std::size_t i) -> const Eigen::Vector3d& { return points[i]; },
        point_sigma, viewpoint);
}

FittedPlane fit_plane(std::span<const Eigen::Vector3d> cloud,
                      std::span<const std::uint32_t> indices, double point_sigma,
                      const Eigen::Vector3d& viewpoint) {
    return fit(
        indices.size(), [&](std::size_t i) -> const Eigen::Vector3d& { return cloud[indices[i]]; },
        point_sigma, viewpoint);
}

}  // namespace tlsmon::registration
