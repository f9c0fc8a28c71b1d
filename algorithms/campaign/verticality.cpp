#include "algorithms/campaign/verticality.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "algorithms/campaign/point_grid.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

const char* class_name(VerticalityClass c) {
    switch (c) {
        case VerticalityClass::vertical:
            return "vertical";
        case VerticalityClass::horizontal:
            return "horizontal";
        case VerticalityClass::other:
            return "other";
        case VerticalityClass::undefined:
            break;
    }
    return "undefined";
}

VerticalityClass classify(double v, const VerticalityParameters& p) {
    if (!std::isfinite(v)) return VerticalityClass::undefined;
    if (v >= p.vertical_min) return VerticalityClass::vertical;
    if (v <= p.horizontal_max) return VerticalityClass::horizontal;
    return VerticalityClass::other;
}

void validate(const VerticalityParameters& p) {
    if (!(p.radius > 0 && p.radius <= 100)) throw Error("campaign: radius must lie in (0, 100] m");
    if (p.min_neighbours < 3) throw Error("campaign: min_neighbours must be at least 3");
    if (!(p.horizontal_max >= 0 && p.horizontal_max < p.vertical_min && p.vertical_min <= 1))
        throw Error("campaign: need 0 ≤ horizontal_max < vertical_min ≤ 1");
}

std::vector<float> verticality(std::span<const Eigen::Vector3d> points,
                               const VerticalityParameters& p, unsigned threads) {
    validate(p);
    const PointGrid grid(points, p.radius);
    std::vector<float> out(points.size(), std::numeric_limits<float>::quiet_NaN());
    parallel_for(
        points.size(),
        [&](std::size_t i) {
            if (!points[i].allFinite()) return;
            // The structure tensor about the neighbours' mean (Welford-free: the offsets from
            // the query point keep the sums small).
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
            int n = 0;
            grid.within(points[i], p.radius, [&](std::uint32_t k, double) {
                const Eigen::Vector3d d = points[k] - points[i];
                sum += d;
                outer += d * d.transpose();
                ++n;
            });
            if (n < p.min_neighbours) return;
            const Eigen::Vector3d mean = sum / n;
            const Eigen::Matrix3d covariance = outer / n - mean * mean.transpose();
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
            const Eigen::Vector3d e3 = eigen.eigenvectors().col(0);  // smallest eigenvalue
            out[i] = float(1.0 - std::abs(e3.z()));
        },
        threads);
    return out;
}

}  // namespace tlsmon::campaign
