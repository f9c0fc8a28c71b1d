// The cubic B-spline interpolant (cubic_bspline.hpp) against known answers: it passes
// through every sample; a sampled sinusoid comes back as the spline's transfer function says
// (its phase error at a quarter pixel is what a correlation's shift is pulled by); its
// gradient is the derivative of its values; a run of valid pixels is filtered on its own,
// mirrored at its ends, whatever lies beyond an empty pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "algorithms/cubic_bspline.hpp"

namespace {

using tlsmon::BSplineImage;
using tlsmon::CubicSample;
using tlsmon::Image;

Image random_image(Eigen::Index rows, Eigen::Index columns, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Image im{Eigen::ArrayXXd(rows, columns), tlsmon::ImageMask::Constant(rows, columns, true)};
    for (Eigen::Index r = 0; r < rows; ++r)
        for (Eigen::Index c = 0; c < columns; ++c) im.value(r, c) = u(rng);
    return im;
}

double beta3(double t) {
    const double s = std::abs(t);
    return s < 1 ? 2.0 / 3 - s * s + s * s * s / 2 : s < 2 ? (2 - s) * (2 - s) * (2 - s) / 6 : 0;
}

TEST(CubicBSpline, PassesThroughEverySample) {
    Image im = random_image(30, 40, 1);
    im.valid(12, 17) = false;
    const BSplineImage spline = tlsmon::bspline_image(im);
    int checked = 0;
    CubicSample s;
    for (Eigen::Index r = 1; r + 2 < im.rows(); ++r)
        for (Eigen::Index c = 1; c + 2 < im.columns(); ++c) {
            if (!tlsmon::bspline_interpolate(spline, double(r), double(c), s)) continue;
            EXPECT_NEAR(s.value, im.value(r, c), 1e-12) << r << ", " << c;
            ++checked;
        }
    EXPECT_GT(checked, 900);
    // The empty pixel: no interpolant needing it.
    EXPECT_FALSE(tlsmon::bspline_interpolate(spline, 12.5, 16.5, s));
    EXPECT_FALSE(tlsmon::bspline_interpolate(spline, 10.2, 15.9, s));
}

// cos(ωx) along the columns, at x = x₀ + t: Re[e^{iωx₀} H(ω, t)] with
// H(ω, t) = Σ_k β³(t − k) e^{iωk} / ((4 + 2 cos ω)/6), the cardinal spline's response.
TEST(CubicBSpline, ASinusoidComesBackAsTheSplinesTransferFunctionSays) {
    const double f = 0.2, w = 2 * std::numbers::pi * f;
    Image im{Eigen::ArrayXXd(8, 200), tlsmon::ImageMask::Constant(8, 200, true)};
    for (Eigen::Index c = 0; c < 200; ++c) im.value.col(c).setConstant(std::cos(w * double(c)));
    const BSplineImage spline = tlsmon::bspline_image(im);
    for (const double t : {0.125, 0.25, 0.5, 0.75}) {
        std::complex<double> h = 0;
        for (int k = -2; k <= 3; ++k) h += beta3(t - k) * std::polar(1.0, w * k);
        h /= (4 + 2 * std::cos(w)) / 6;
        for (const int x0 : {60, 97, 131}) {
            CubicSample s;
            ASSERT_TRUE(tlsmon::bspline_interpolate(spline, 3.0, x0 + t, s));
            EXPECT_NEAR(s.value, (std::polar(1.0, w * x0) * h).real(), 1e-10) << t << " " << x0;
        }
        // The phase error as a shift: 0.0025 pixel at a quarter pixel (Keys' kernel: 0.027).
        const double pull = -std::arg(h * std::polar(1.0, -w * t)) / w;
        if (t == 0.25) {
            EXPECT_NEAR(pull, 0.0025, 0.0001);
        } else if (t == 0.5) {
            EXPECT_NEAR(pull, 0.0, 1e-12);
        }
    }
}

TEST(CubicBSpline, TheGradientIsTheDerivativeOfTheValues) {
    const BSplineImage spline = tlsmon::bspline_image(random_image(20, 20, 2));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(2.0, 17.0);
    const double h = 1e-6;
    for (int k = 0; k < 50; ++k) {
        const double r = u(rng), c = u(rng);
        CubicSample s, a, b, d, e;
        ASSERT_TRUE(tlsmon::bspline_interpolate(spline, r, c, s));
        ASSERT_TRUE(tlsmon::bspline_interpolate(spline, r + h, c, a));
        ASSERT_TRUE(tlsmon::bspline_interpolate(spline, r - h, c, b));
        ASSERT_TRUE(tlsmon::bspline_interpolate(spline, r, c + h, d));
        ASSERT_TRUE(tlsmon::bspline_interpolate(spline, r, c - h, e));
        EXPECT_NEAR(s.d_row, (a.value - b.value) / (2 * h), 1e-6);
        EXPECT_NEAR(s.d_column, (d.value - e.value) / (2 * h), 1e-6);
    }
}

// A row of runs 5, 30 and 5 pixels long between empty pixels: each run's coefficients
// satisfy (c(k−1) + 4 c(k) + c(k+1))/6 = s(k) with its mirrored ends, c(−1) = c(1),
// c(n) = c(n − 2); the short runs take the closed-form start, the long one the truncated sum.
TEST(CubicBSpline, EachRunIsFilteredOnItsOwnWithMirroredEnds) {
    Image im = random_image(1, 42, 4);
    im.valid(0, 5) = im.valid(0, 36) = false;
    const BSplineImage spline = tlsmon::bspline_image(im);
    const auto& c = spline.coefficients.value;
    for (const auto& [first, n] : {std::pair{0, 5}, std::pair{6, 30}, std::pair{37, 5}}) {
        const auto at = [&](int k) {
            return c(0, first + (k < 0 ? -k : k >= n ? 2 * n - 2 - k : k));
        };
        for (int k = 0; k < n; ++k)
            EXPECT_NEAR((at(k - 1) + 4 * at(k) + at(k + 1)) / 6, im.value(0, first + k), 1e-10)
                << "run at " << first << ", pixel " << k;
    }
    EXPECT_FALSE(spline.coefficients.valid(0, 5));
    // What lies beyond an empty pixel changes nothing on this side.
    Image other = im;
    other.value(0, 40) += 1.0;
    EXPECT_TRUE(
        (tlsmon::bspline_image(other).coefficients.value.leftCols(36) == c.leftCols(36)).all());
}

}  // namespace
