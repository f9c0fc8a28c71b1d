#include "algorithms/cubic_bspline.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace tlsmon {

namespace {

const double kPole = std::sqrt(3.0) - 2.0;  // z of β³'s sampled kernel (1 4 1)/6
// c⁺(0)'s sum is truncated where |z|^k < 1e-12: 21 terms.
const auto kHorizon = static_cast<Eigen::Index>(std::ceil(std::log(1e-12) / std::log(-kPole)));

// The coefficients of one run c[0..n) in place (Unser 1999, Box 2): the gain
// (1 − z)(1 − 1/z) = 6 and a causal pass started by the mirror-symmetric sum, then an
// anticausal pass started from its last value.
void coefficients_of_run(double* c, Eigen::Index n) {
    if (n < 2) return;  // one sample: its own coefficient
    const double z = kPole;
    double sum = 0.0;
    if (kHorizon < n) {
        double zk = 1.0;
        for (Eigen::Index k = 0; k < kHorizon; ++k, zk *= z) sum += zk * c[k];
    } else {
        // The mirror-symmetric extension of period 2n − 2, summed in closed form.
        double zk = z, z2k = std::pow(z, double(n - 1));
        sum = c[0] + z2k * c[n - 1];
        z2k *= z2k / z;
        for (Eigen::Index k = 1; k < n - 1; ++k, zk *= z, z2k /= z) sum += (zk + z2k) * c[k];
        sum /= 1.0 - zk * zk;
    }
    c[0] = 6.0 * sum;
    for (Eigen::Index k = 1; k < n; ++k) c[k] = 6.0 * c[k] + z * c[k - 1];
    c[n - 1] = z / (z * z - 1.0) * (z * c[n - 2] + c[n - 1]);
    for (Eigen::Index k = n - 2; k >= 0; --k) c[k] = z * (c[k + 1] - c[k]);
}

// Every maximal run of valid pixels down each column of (values, valid), contiguous in
// Eigen's column-major storage.
void filter_columns(Eigen::ArrayXXd& values, const ImageMask& valid) {
    for (Eigen::Index column = 0; column < values.cols(); ++column) {
        double* line = &values(0, column);
        for (Eigen::Index k = 0; k < values.rows();) {
            if (!valid(k, column)) {
                ++k;
                continue;
            }
            Eigen::Index end = k;
            while (end < values.rows() && valid(end, column)) ++end;
            coefficients_of_run(line + k, end - k);
            k = end;
        }
    }
}

// β³(t) and its derivative.
double bspline(double t) {
    const double s = std::abs(t);
    if (s < 1.0) return 2.0 / 3.0 - s * s + 0.5 * s * s * s;
    if (s < 2.0) return (2.0 - s) * (2.0 - s) * (2.0 - s) / 6.0;
    return 0.0;
}

double bspline_derivative(double t) {
    const double s = std::abs(t), sign = t < 0.0 ? -1.0 : 1.0;
    if (s < 1.0) return sign * (-2.0 * s + 1.5 * s * s);
    if (s < 2.0) return -sign * 0.5 * (2.0 - s) * (2.0 - s);
    return 0.0;
}

}  // namespace

BSplineImage bspline_image(const Image& samples) {
    BSplineImage out{samples};
    Eigen::ArrayXXd& c = out.coefficients.value;
    const ImageMask& valid = out.coefficients.valid;
    c = valid.select(c, 0.0);
    // Along the rows, a block of rows at a time transposed into a buffer (a row is strided in
    // column-major storage: the whole image transposed took ten times the filtering).
    constexpr Eigen::Index kBlock = 32;
    for (Eigen::Index first = 0; first < c.rows(); first += kBlock) {
        const Eigen::Index n = std::min(kBlock, c.rows() - first);
        Eigen::ArrayXXd rows = c.middleRows(first, n).transpose();
        filter_columns(rows, valid.middleRows(first, n).transpose());
        c.middleRows(first, n) = rows.transpose();
    }
    filter_columns(c, valid);
    return out;
}

bool bspline_interpolate(const BSplineImage& image, double row, double column, CubicSample& out) {
    // f = Σ_i Σ_j β³(row − r_i) β³(column − c_j) c(r_i, c_j) over r_i = ⌊row⌋ − 1 … ⌊row⌋ + 2.
    const Image& c = image.coefficients;
    const double fr = std::floor(row), fc = std::floor(column);
    const auto r0 = static_cast<Eigen::Index>(fr) - 1, c0 = static_cast<Eigen::Index>(fc) - 1;
    if (r0 < 0 || c0 < 0 || r0 + 3 >= c.rows() || c0 + 3 >= c.columns()) return false;
    std::array<double, 4> wr{}, wc{}, dr{}, dc{};
    for (int k = 0; k < 4; ++k) {
        const double tr = row - fr - (k - 1), tc = column - fc - (k - 1);
        wr[k] = bspline(tr);
        dr[k] = bspline_derivative(tr);
        wc[k] = bspline(tc);
        dc[k] = bspline_derivative(tc);
    }
    out = {};
    for (int i = 0; i < 4; ++i) {
        double value = 0.0, slope = 0.0;  // along row i: the value and its column derivative
        for (int j = 0; j < 4; ++j) {
            if (!c.valid(r0 + i, c0 + j)) return false;
            const double v = c.value(r0 + i, c0 + j);
            value += wc[j] * v;
            slope += dc[j] * v;
        }
        out.value += wr[i] * value;
        out.d_row += dr[i] * value;
        out.d_column += wr[i] * slope;
    }
    return true;
}

}  // namespace tlsmon
