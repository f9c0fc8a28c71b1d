#include "algorithms/registration/supervoxel_change.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.hpp"

namespace tlsmon::registration {

SupervoxelPatch patch_of(std::span<const Eigen::Vector3d> points,
                         const Eigen::Vector3d& viewpoint) {
    if (points.size() < 3) throw Error("supervoxel patch: fewer than 3 points");
    SupervoxelPatch p;
    p.samples = points.size();
    for (const auto& x : points) p.centroid += x;
    p.centroid /= static_cast<double>(points.size());
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& x : points) {
        const Eigen::Vector3d d = x - p.centroid;
        C += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    const Eigen::Vector3d l = es.eigenvalues().cwiseMax(0.0);  // ascending
    const double total = l.sum();
    p.surface_variation = total > 0 ? l(0) / total : 1.0;
    p.spread = l(2) > 0 ? l(1) / l(2) : 0.0;
    p.sigma = std::sqrt(l(0) / static_cast<double>(points.size()));
    p.normal = es.eigenvectors().col(0).normalized();
    if (p.normal.dot(viewpoint - p.centroid) < 0) p.normal = -p.normal;
    return p;
}

SupervoxelChange change_of(const SupervoxelPatch& patch, std::span<const double> distances,
                           double registration_sigma, double z) {
    SupervoxelChange c;
    c.samples = distances.size();
    if (c.samples < 2) throw Error("supervoxel change: fewer than 2 distances");
    double sum = 0;
    for (const double d : distances) sum += d;
    c.change = sum / static_cast<double>(c.samples);
    double ss = 0;
    for (const double d : distances) ss += (d - c.change) * (d - c.change);
    c.sigma_epoch = std::sqrt(ss / static_cast<double>(c.samples - 1));
    const double m = static_cast<double>(patch.samples);
    c.lod = z * std::sqrt(c.sigma_epoch * c.sigma_epoch / static_cast<double>(c.samples) +
                          patch.sigma * patch.sigma / m + registration_sigma * registration_sigma);
    return c;
}

}  // namespace tlsmon::registration
