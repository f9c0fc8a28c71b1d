#include "algorithms/patches/patch_plane.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace tlsmon::patches {

PatchFrame PatchFrame::about(const Eigen::Vector3d& origin, const Eigen::Vector3d& normal) {
    PatchFrame f;
    f.origin = origin;
    f.normal = normal.normalized();
    // u: the unit axis least aligned with n, made square to it.
    Eigen::Index least = 0;
    f.normal.cwiseAbs().minCoeff(&least);
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(least);
    f.u = (axis - f.normal * f.normal.dot(axis)).normalized();
    f.v = f.normal.cross(f.u);
    return f;
}

PlaneMoments& PlaneMoments::operator+=(const PlaneMoments& o) {
    m += o.m, su += o.su, sv += o.sv, sw += o.sw;
    suu += o.suu, suv += o.suv, svv += o.svv;
    suw += o.suw, svw += o.svw, sww += o.sww;
    return *this;
}

PlaneFit fit_plane(const PlaneMoments& s) {
    PlaneFit f;
    f.count = s.count();
    if (s.m < 4) return f;
    const double m = s.m, u = s.su / m, v = s.sv / m, w = s.sw / m;
    // Centred sums: Σ(u − ū)² = Σu² − m·ū², and so on.
    f.slope_normal << s.suu - m * u * u, s.suv - m * u * v, s.suv - m * u * v, s.svv - m * v * v;
    const Eigen::Vector2d rhs(s.suw - m * u * w, s.svw - m * v * w);
    const double sww = s.sww - m * w * w;
    const double det = f.slope_normal.determinant();
    // Points along a line (or one point) leave a slope free.
    if (!(det > 1e-12 * f.slope_normal.trace() * f.slope_normal.trace())) return f;
    f.centroid = {u, v};
    f.height = w;
    f.slope = f.slope_normal.inverse() * rhs;
    f.sigma = std::sqrt(std::max(0.0, sww - f.slope.dot(rhs)) / (m - 3));
    f.valid = true;
    return f;
}

std::vector<std::uint8_t> plane_inliers(const std::vector<Eigen::Vector3f>& uvw, double clip,
                                        int rounds) {
    std::vector<std::uint8_t> keep(uvw.size(), 1);
    PlaneMoments kept;
    for (const auto& p : uvw) kept.add(p.cast<double>());
    std::vector<double> residual(uvw.size()), spread;
    for (int round = 0; round < rounds; ++round) {
        const PlaneFit fit = fit_plane(kept);
        if (!fit.valid) break;
        for (std::size_t i = 0; i < uvw.size(); ++i)
            residual[i] = double(uvw[i].z()) - fit.height_at(uvw[i].head<2>().cast<double>());
        spread = residual;
        const auto mid = spread.begin() + long(spread.size() / 2);
        std::nth_element(spread.begin(), mid, spread.end());
        const double centre = *mid;
        for (auto& r : spread) r = std::abs(r - centre);
        std::nth_element(spread.begin(), mid, spread.end());
        // A floor of 1 µm: points exactly on a plane have no spread to clip by.
        const double limit = clip * std::max(1.4826 * *mid, 1e-6);
        PlaneMoments next;
        for (std::size_t i = 0; i < uvw.size(); ++i) {
            keep[i] = std::abs(residual[i] - centre) <= limit;
            if (keep[i]) next.add(uvw[i].cast<double>());
        }
        const bool settled = next.m == kept.m;
        kept = next;
        if (settled) break;
    }
    return keep;
}

PlaneMoments inlier_moments(const std::vector<Eigen::Vector3f>& uvw, double clip, int rounds) {
    const auto keep = plane_inliers(uvw, clip, rounds);
    PlaneMoments kept;
    for (std::size_t i = 0; i < uvw.size(); ++i)
        if (keep[i]) kept.add(uvw[i].cast<double>());
    return kept;
}

double PlaneFit::height_sigma_at(const Eigen::Vector2d& at) const {
    if (!valid) return std::numeric_limits<double>::quiet_NaN();
    const Eigen::Vector2d g = at - centroid;
    return sigma * std::sqrt(1.0 / double(count) + g.dot(slope_normal.inverse() * g));
}

}  // namespace tlsmon::patches
