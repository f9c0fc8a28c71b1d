#include "algorithms/patches/zone_median.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "algorithms/m3c2/zone_uncertainty.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::patches {

namespace {

// The weighted least-squares gradient of d over x among the patches `use` keeps:
// (Σ w X Xᵀ)⁺ Σ w X (d − d̄), X = x − x̄, the pseudo-inverse over the directions the
// positions span (eigenvalues above 1e-6 of the largest).
Eigen::Vector3d gradient_of(std::span<const PatchChange> patches, const std::vector<bool>& use) {
    double w_sum = 0, d_mean = 0;
    Eigen::Vector3d x_mean = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < patches.size(); ++k) {
        if (!use[k]) continue;
        const double w = double(patches[k].cells.size());
        w_sum += w;
        d_mean += w * patches[k].distance;
        x_mean += w * patches[k].at;
    }
    if (!(w_sum > 0)) return Eigen::Vector3d::Zero();
    d_mean /= w_sum;
    x_mean /= w_sum;
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < patches.size(); ++k) {
        if (!use[k]) continue;
        const double w = double(patches[k].cells.size());
        const Eigen::Vector3d X = patches[k].at - x_mean;
        N += w * X * X.transpose();
        b += w * X * (patches[k].distance - d_mean);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(N);
    const Eigen::Vector3d& lambda = eigen.eigenvalues();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i)
        if (lambda[i] > 1e-6 * lambda[2] && lambda[i] > 0)
            g += eigen.eigenvectors().col(i) * (eigen.eigenvectors().col(i).dot(b) / lambda[i]);
    return g;
}

}  // namespace

ArealMedian areal_median(std::span<const PatchChange> patches) {
    for (std::size_t k = 0; k < patches.size(); ++k) {
        const auto& p = patches[k];
        if (!std::isfinite(p.distance) || !p.at.allFinite() || !(p.sampling_sigma >= 0) ||
            !std::isfinite(p.sampling_sigma))
            throw Error("zone median: patch " + std::to_string(k) +
                        " has a non-finite distance or place, or a negative or non-finite σ");
    }
    ArealMedian out;
    // ĝ, then again without the patches far from its plane (a patch that moved alone).
    std::vector<bool> use(patches.size(), true);
    out.gradient = patches.size() >= 3 ? gradient_of(patches, use) : Eigen::Vector3d::Zero();
    if (patches.size() >= 3) {
        std::vector<double> residual(patches.size());
        for (std::size_t k = 0; k < patches.size(); ++k)
            residual[k] = patches[k].distance - out.gradient.dot(patches[k].at);
        const auto [centre, mad] = median_and_mad(residual);
        const double limit = 3.5 * kMadToSigma * mad;
        bool dropped = false;
        for (std::size_t k = 0; k < patches.size(); ++k)
            if (std::abs(residual[k] - centre) > limit && limit > 0) use[k] = false, dropped = true;
        if (dropped) out.gradient = gradient_of(patches, use);
    }
    // Every cell one vote, with the change at its place; each patch one member.
    std::vector<double> values, sigma;
    std::vector<std::size_t> first{0};
    for (const auto& p : patches) {
        for (const auto& x : p.cells) {
            if (!x.allFinite()) throw Error("zone median: a footprint cell is not finite");
            values.push_back(p.distance + out.gradient.dot(x - p.at));
        }
        first.push_back(values.size());
        sigma.push_back(p.sampling_sigma);
    }
    out.cells = values.size();
    if (values.empty()) return out;
    out.sampling_variance = m3c2::median_sampling_variance(values, first, sigma);
    out.value = median(std::move(values));
    return out;
}

}  // namespace tlsmon::patches
