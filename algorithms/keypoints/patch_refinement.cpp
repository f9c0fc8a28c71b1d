#include "algorithms/keypoints/patch_refinement.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "algorithms/image_correlation.hpp"

namespace tlsmon::keypoints {

std::optional<IntensityPatch> intensity_patch(const Image& im, int row, int column, int radius) {
    if (row - radius < 0 || column - radius < 0 || row + radius >= im.rows() ||
        column + radius >= im.columns())
        return std::nullopt;
    IntensityPatch p;
    p.row = row;
    p.column = column;
    p.radius = radius;
    p.values.reserve(static_cast<std::size_t>((2 * radius + 1) * (2 * radius + 1)));
    for (int i = -radius; i <= radius; ++i) {
        for (int j = -radius; j <= radius; ++j) {
            if (!im.valid(row + i, column + j)) return std::nullopt;
            p.values.push_back(static_cast<float>(im.value(row + i, column + j)));
        }
    }
    return p;
}

namespace {

// One pass of a separable Gaussian along the rows (`down`) or the columns of `a`, as shifted
// whole-array sums (each a vectorised block operation); zero beyond the edges.
Eigen::ArrayXXd gaussian_pass(const Eigen::ArrayXXd& a, const std::vector<double>& g, bool down) {
    const auto half = static_cast<Eigen::Index>(g.size() / 2);
    const Eigen::Index length = down ? a.rows() : a.cols();
    Eigen::ArrayXXd out = Eigen::ArrayXXd::Zero(a.rows(), a.cols());
    for (Eigen::Index k = -half; k <= half; ++k) {
        const Eigen::Index first = std::max<Eigen::Index>(0, -k);
        const Eigen::Index n = std::min(length, length - k) - first;
        if (n <= 0) continue;
        const double w = g[static_cast<std::size_t>(k + half)];
        if (down)
            out.middleRows(first, n) += w * a.middleRows(first + k, n);
        else
            out.middleCols(first, n) += w * a.middleCols(first + k, n);
    }
    return out;
}

}  // namespace

Image gaussian_prefiltered(const SphericalImages& im, double sigma) {
    Image out{im.intensity, im.valid};
    if (!(sigma > 0)) return out;
    const int half = static_cast<int>(std::ceil(3 * sigma));
    std::vector<double> g(static_cast<std::size_t>(2 * half + 1));
    for (int k = -half; k <= half; ++k)
        g[static_cast<std::size_t>(k + half)] = std::exp(-0.5 * k * k / (sigma * sigma));
    // Normalised convolution (Knutsson & Westin 1993): the blurred intensity over the blurred
    // mask, so an empty pixel neither darkens its neighbours nor is filled.
    const Eigen::ArrayXXd weight = im.valid.cast<double>();
    const Eigen::ArrayXXd value =
        gaussian_pass(gaussian_pass(im.intensity * weight, g, true), g, false);
    const Eigen::ArrayXXd share = gaussian_pass(gaussian_pass(weight, g, true), g, false);
    out.value = im.valid.select(value / share.max(1e-300), 0.0);
    return out;
}

std::optional<PatchMatch> match_patch(const IntensityPatch& patch, const BSplineImage& epoch,
                                      double row, double column,
                                      const PatchMatchParameters& parameters) {
    const int r = patch.radius;
    double dy = row - patch.row, dx = column - patch.column;  // the shift sought
    const double start_y = dy, start_x = dx;
    double gain = 1, offset = 0;
    // The reference patch's gradient by central differences, at its interior pixels: the
    // Jacobian of E(p + s) ≈ g·P(p) + o is taken as g·∇P (Baker & Matthews 2004, "Lucas-Kanade
    // 20 years on", the inverse formulation), so the epoch's noise never enters it (with ∇E,
    // Σ v·∇E correlates the noise with its own gradient and pulls the shift).
    const int side = 2 * r + 1;
    const auto at = [&](int i, int j) {
        return double(patch.values[static_cast<std::size_t>((i + r) * side + (j + r))]);
    };
    CubicSample e;
    for (int it = 1; it <= parameters.max_iterations; ++it) {
        // Normal equations of v = E(p + s) − (g·P + o) in (Δy, Δx, g, o).
        Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
        Eigen::Vector4d u = Eigen::Vector4d::Zero();
        for (int i = -r + 1; i < r; ++i) {
            for (int j = -r + 1; j < r; ++j) {
                if (!bspline_interpolate(epoch, patch.row + i + dy, patch.column + j + dx, e))
                    return std::nullopt;
                const double p = at(i, j);
                const Eigen::Vector4d a(gain * 0.5 * (at(i + 1, j) - at(i - 1, j)),
                                        gain * 0.5 * (at(i, j + 1) - at(i, j - 1)), -p, -1.0);
                const double residual = e.value - (gain * p + offset);
                N.noalias() += a * a.transpose();
                u.noalias() -= a * residual;
            }
        }
        const Eigen::LDLT<Eigen::Matrix4d> ldlt(N);
        if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return std::nullopt;
        const Eigen::Vector4d step = ldlt.solve(u);
        if (!step.allFinite()) return std::nullopt;
        dy += step[0];
        dx += step[1];
        gain += step[2];
        offset += step[3];
        if (std::hypot(dy - start_y, dx - start_x) > parameters.max_move || !(gain > 0))
            return std::nullopt;
        if (std::hypot(step[0], step[1]) < parameters.tolerance) {
            // Normalised cross-correlation at the solution.
            Eigen::ArrayXd p(patch.values.size()), q(patch.values.size());
            Eigen::Index k = 0;
            for (int i = -r; i <= r; ++i) {
                for (int j = -r; j <= r; ++j, ++k) {
                    if (!bspline_interpolate(epoch, patch.row + i + dy, patch.column + j + dx, e))
                        return std::nullopt;
                    p[k] = patch.values[static_cast<std::size_t>(k)];
                    q[k] = e.value;
                }
            }
            const double correlation = normalised_cross_correlation(p, q);
            if (correlation < parameters.min_correlation) return std::nullopt;
            return PatchMatch{patch.row + dy, patch.column + dx, correlation, it};
        }
    }
    return std::nullopt;
}

}  // namespace tlsmon::keypoints
