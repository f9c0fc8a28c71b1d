#include "algorithms/m3c2/normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "algorithms/m3c2/members.hpp"
#include "algorithms/m3c2/region_index.hpp"

namespace tlsmon::m3c2 {

Eigen::Vector3d oriented(const Eigen::Vector3d& normal, const Eigen::Vector3d& c,
                         const Orientation& orientation) {
    const Eigen::Vector3d v = orientation.kind == Orientation::Kind::vector
                                  ? orientation.value
                                  : Eigen::Vector3d(orientation.value - c);
    return normal.dot(v) < 0.0 ? Eigen::Vector3d(-normal) : normal;
}

CoreNormal normal_at(const Eigen::Vector3d& c, const std::vector<Eigen::Vector3d>& cloud,
                     std::span<const std::uint32_t> neighbours,
                     const NormalParameters& parameters) {
    CoreNormal best;
    double best_planarity = -std::numeric_limits<double>::infinity();
    // Coordinates relative to c and distances, once for every radius.
    std::vector<Eigen::Vector3d> offset(neighbours.size());
    std::vector<double> distance(neighbours.size());
    for (std::size_t j = 0; j < neighbours.size(); ++j) {
        offset[j] = cloud[neighbours[j]] - c;
        distance[j] = offset[j].norm();
    }
    for (double r : parameters.radii) {
        // Two passes: the mean, then the spread about it.
        std::size_t n = 0;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (std::size_t j = 0; j < offset.size(); ++j)
            if (distance[j] <= r) {
                sum += offset[j];
                ++n;
            }
        if (n < 3) continue;
        const Eigen::Vector3d mean = sum / static_cast<double>(n);
        Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
        for (std::size_t j = 0; j < offset.size(); ++j)
            if (distance[j] <= r) {
                const Eigen::Vector3d e = offset[j] - mean;
                covariance.noalias() += e * e.transpose();
            }
        covariance /= static_cast<double>(n - 1);
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
        const Eigen::Vector3d l = solver.eigenvalues();  // ascending
        if (!(l[2] > 0.0)) continue;                     // all points at one place
        const double planarity = (l[1] - l[0]) / l[2];
        if (planarity > best_planarity) {
            best_planarity = planarity;
            best.normal = solver.eigenvectors().col(0).normalized();
            best.radius = r;
        }
    }
    if (best.defined()) best.normal = oriented(best.normal, c, parameters.orientation);
    return best;
}

std::vector<CoreNormal> estimate_normals(const std::vector<Eigen::Vector3d>& cloud,
                                         const std::vector<Eigen::Vector3d>& core_points,
                                         const NormalParameters& parameters, unsigned threads,
                                         std::span<const std::uint8_t> left_out) {
    validate(parameters);
    const double largest = *std::max_element(parameters.radii.begin(), parameters.radii.end());
    const RegionIndex index = RegionIndex::spheres(core_points, largest, largest / 2, threads);
    std::vector<CoreNormal> normals(core_points.size());
    for_each_core_with_members(
        cloud, index, core_points.size(),
        [&](std::uint32_t k, const Eigen::Vector3d& p) {
            return (p - core_points[k]).norm() <= largest;
        },
        [&](std::size_t k, std::span<const std::uint32_t> neighbours) {
            normals[k] = normal_at(core_points[k], cloud, neighbours, parameters);
        },
        threads, kMemberBudget, /*single_pass=*/false,  // spheres hold ~1000 points each
        left_out);
    return normals;
}

}  // namespace tlsmon::m3c2
