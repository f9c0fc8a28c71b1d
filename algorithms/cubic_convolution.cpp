#include "algorithms/cubic_convolution.hpp"

#include <array>
#include <cmath>

namespace tlsmon {

namespace {

constexpr double kA = -0.5;

double keys(double t) {
    const double s = std::abs(t);
    if (s <= 1.0) return ((kA + 2.0) * s - (kA + 3.0)) * s * s + 1.0;
    if (s < 2.0) return ((kA * s - 5.0 * kA) * s + 8.0 * kA) * s - 4.0 * kA;
    return 0.0;
}

double keys_derivative(double t) {
    const double s = std::abs(t), sign = t < 0.0 ? -1.0 : 1.0;
    if (s <= 1.0) return sign * (3.0 * (kA + 2.0) * s - 2.0 * (kA + 3.0)) * s;
    if (s < 2.0) return sign * ((3.0 * kA * s - 10.0 * kA) * s + 8.0 * kA);
    return 0.0;
}

}  // namespace

bool cubic_interpolate(const Image& im, double row, double column, CubicSample& out) {
    const double fr = std::floor(row), fc = std::floor(column);
    const auto r0 = static_cast<Eigen::Index>(fr) - 1, c0 = static_cast<Eigen::Index>(fc) - 1;
    if (r0 < 0 || c0 < 0 || r0 + 3 >= im.rows() || c0 + 3 >= im.columns()) return false;
    std::array<double, 4> wr{}, wc{}, dr{}, dc{};
    for (int k = 0; k < 4; ++k) {
        const double tr = row - fr - (k - 1), tc = column - fc - (k - 1);
        wr[k] = keys(tr);
        dr[k] = keys_derivative(tr);
        wc[k] = keys(tc);
        dc[k] = keys_derivative(tc);
    }
    out = {};
    for (int i = 0; i < 4; ++i) {
        double value = 0.0, slope = 0.0;  // along row i: the value and its column derivative
        for (int j = 0; j < 4; ++j) {
            if (!im.valid(r0 + i, c0 + j)) return false;
            const double v = im.value(r0 + i, c0 + j);
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
