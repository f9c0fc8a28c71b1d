#include "algorithms/keypoints/patch_refinement.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace tlsmon::keypoints {

std::optional<IntensityPatch> intensity_patch(const SphericalImages& im, int row, int column,
                                              int radius) {
    if (row - radius < 0 || column - radius < 0 || row + radius >= im.rows ||
        column + radius >= im.columns)
        return std::nullopt;
    IntensityPatch p;
    p.row = row;
    p.column = column;
    p.radius = radius;
    p.values.reserve(static_cast<std::size_t>((2 * radius + 1) * (2 * radius + 1)));
    for (int i = -radius; i <= radius; ++i) {
        for (int j = -radius; j <= radius; ++j) {
            if (!im.valid(row + i, column + j)) return std::nullopt;
            p.values.push_back(static_cast<float>(im.intensity(row + i, column + j)));
        }
    }
    return p;
}

namespace {

// E and its gradient (central differences at the pixels) bilinearly interpolated at (y, x);
// false when a pixel needed is outside the image or empty.
struct Sample {
    double value = 0, d_row = 0, d_column = 0;
};

bool sample(const SphericalImages& im, double y, double x, Sample& s) {
    const int r0 = static_cast<int>(std::floor(y)), c0 = static_cast<int>(std::floor(x));
    if (r0 < 1 || c0 < 1 || r0 + 2 >= im.rows || c0 + 2 >= im.columns) return false;
    const double fy = y - r0, fx = x - c0;
    s = {};
    for (int a = 0; a <= 1; ++a) {
        for (int b = 0; b <= 1; ++b) {
            const int r = r0 + a, c = c0 + b;
            if (!im.valid(r, c) || !im.valid(r - 1, c) || !im.valid(r + 1, c) ||
                !im.valid(r, c - 1) || !im.valid(r, c + 1))
                return false;
            const double w = (a ? fy : 1 - fy) * (b ? fx : 1 - fx);
            s.value += w * im.intensity(r, c);
            s.d_row += w * 0.5 * (im.intensity(r + 1, c) - im.intensity(r - 1, c));
            s.d_column += w * 0.5 * (im.intensity(r, c + 1) - im.intensity(r, c - 1));
        }
    }
    return true;
}

}  // namespace

std::optional<PatchMatch> match_patch(const IntensityPatch& patch, const SphericalImages& epoch,
                                      double row, double column,
                                      const PatchMatchParameters& parameters) {
    const int r = patch.radius;
    const std::size_t n = patch.values.size();
    double dy = row - patch.row, dx = column - patch.column;  // the shift sought
    const double start_y = dy, start_x = dx;
    double gain = 1, offset = 0;
    std::vector<Sample> e(n);
    for (int it = 1; it <= parameters.max_iterations; ++it) {
        // Normal equations of P − (g·E + o) in (Δy, Δx, g, o).
        Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
        Eigen::Vector4d u = Eigen::Vector4d::Zero();
        std::size_t k = 0;
        for (int i = -r; i <= r; ++i) {
            for (int j = -r; j <= r; ++j, ++k) {
                if (!sample(epoch, patch.row + i + dy, patch.column + j + dx, e[k]))
                    return std::nullopt;
                const Eigen::Vector4d a(gain * e[k].d_row, gain * e[k].d_column, e[k].value, 1.0);
                const double residual = patch.values[k] - (gain * e[k].value + offset);
                N.noalias() += a * a.transpose();
                u.noalias() += a * residual;
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
            double sp = 0, se = 0, spp = 0, see = 0, spe = 0;
            k = 0;
            for (int i = -r; i <= r; ++i) {
                for (int j = -r; j <= r; ++j, ++k) {
                    Sample s;
                    if (!sample(epoch, patch.row + i + dy, patch.column + j + dx, s))
                        return std::nullopt;
                    const double p = patch.values[k];
                    sp += p;
                    se += s.value;
                    spp += p * p;
                    see += s.value * s.value;
                    spe += p * s.value;
                }
            }
            const double m = double(n);
            const double cov = spe - sp * se / m;
            const double var = (spp - sp * sp / m) * (see - se * se / m);
            const double correlation = var > 0 ? cov / std::sqrt(var) : 0.0;
            if (correlation < parameters.min_correlation) return std::nullopt;
            return PatchMatch{patch.row + dy, patch.column + dx, correlation, it};
        }
    }
    return std::nullopt;
}

}  // namespace tlsmon::keypoints
