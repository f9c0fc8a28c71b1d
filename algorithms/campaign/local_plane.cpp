#include "algorithms/campaign/local_plane.hpp"

#include <Eigen/Eigenvalues>

#include "algorithms/campaign/point_grid.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

std::vector<LocalPlane> local_planes(std::span<const Eigen::Vector3d> points, double radius,
                                     int min_neighbours, unsigned threads,
                                     std::span<const std::size_t> at) {
    const PointGrid grid(points, radius);
    const std::size_t centres = at.empty() ? points.size() : at.size();
    std::vector<LocalPlane> out(centres);
    parallel_for(
        centres,
        [&](std::size_t j) {
            const std::size_t i = at.empty() ? j : at[j];
            if (!points[i].allFinite()) return;
            // The structure tensor about the neighbours' mean, summed as offsets from the query
            // point so the sums stay small.
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
            int n = 0;
            grid.within(points[i], radius, [&](std::uint32_t k, double) {
                const Eigen::Vector3d d = points[k] - points[i];
                sum += d;
                outer += d * d.transpose();
                ++n;
            });
            if (n < min_neighbours) return;
            const Eigen::Vector3d mean = sum / n;
            const Eigen::Matrix3d covariance = outer / n - mean * mean.transpose();
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
            const Eigen::Vector3d e3 = eigen.eigenvectors().col(0);  // smallest eigenvalue
            out[j].normal = e3.cast<float>();
            out[j].offset = float(e3.dot(points[i] + mean));
            const Eigen::Vector3d lambda = eigen.eigenvalues().cwiseMax(0.0);
            out[j].variation = float(lambda(0) / std::max(lambda.sum(), 1e-300));
        },
        threads);
    return out;
}

}  // namespace tlsmon::campaign
