// Known answers for image correlation: a band-limited image and its copy shifted by a known
// sub-pixel amount (and changed in gain and offset) give back the shift; noise gives an
// error consistent with the returned covariance; a shift outside the search range is not
// reported as found.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "algorithms/image_correlation.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

// A sum of plane waves up to 0.12 cycles per pixel (Nyquist is 0.5): a band-limited
// texture sampled as finely as an orthoimage resampled with a Gaussian kernel of 1.5 pixels
// (whose response at 0.12 cycles per pixel is 0.5). (x, y) = (column, row).
double texture(double x, double y) {
    constexpr double two_pi = 2.0 * std::numbers::pi;
    const double waves[][4] = {{0.031, 0.017, 0.3, 1.0},   {-0.052, 0.081, 1.1, 0.7},
                               {0.113, -0.045, 2.0, 0.5},  {0.071, 0.139, 0.4, 0.4},
                               {-0.157, -0.094, 5.1, 0.3}, {0.191, 0.023, 3.3, 0.25},
                               {0.012, -0.176, 4.2, 0.25}};
    double v = 0.0;
    for (const auto& w : waves) v += w[3] * std::cos(two_pi * 0.6 * (w[0] * x + w[1] * y) + w[2]);
    return v;
}

Image sample(Eigen::Index rows, Eigen::Index columns, double dx, double dy, double gain,
             double offset) {
    Image im;
    im.value.resize(rows, columns);
    im.valid = ImageMask::Constant(rows, columns, true);
    for (Eigen::Index r = 0; r < rows; ++r) {
        for (Eigen::Index c = 0; c < columns; ++c) {
            im.value(r, c) =
                gain * texture(static_cast<double>(c) - dx, static_cast<double>(r) - dy) + offset;
        }
    }
    return im;
}

// Template 41 × 41 placed at (10, 10) in a 61 × 61 search image. With search(p) =
// texture(p − o − s), search(p + o + s) = texture(p) = template(p).
constexpr Eigen::Index kT = 41, kS = 61, kO = 10;

TEST(ImageCorrelation, RecoversKnownSubPixelShifts) {
    const Image templ = sample(kT, kT, 0.0, 0.0, 1.0, 0.0);
    for (const auto& [sx, sy] :
         {std::pair{0.0, 0.0}, {0.25, -0.4}, {1.37, -2.61}, {-3.5, 0.5}, {4.93, 3.08}}) {
        const Image search = sample(kS, kS, kO + sx, kO + sy, 1.7, 0.3);
        CorrelationParameters p;
        p.search_radius = 7;
        const CorrelationResult r = correlate_template(templ, search, {kO, kO}, p);
        ASSERT_TRUE(r.found) << sx << " " << sy;
        EXPECT_NEAR(r.shift.x(), sx, 0.005);
        EXPECT_NEAR(r.shift.y(), sy, 0.005);
        EXPECT_GT(r.ncc, 0.9999);
        EXPECT_GT(r.peak_ncc, 0.8);
    }
}

// Independent noise σ = 0.05 on both images (the texture's rms is ≈ 0.9): over seeded
// trials the error lies within 2 σ of the returned covariance per axis in ≥ 85 % of them
// (the search image's noise kept out of the Jacobian leaves no half-pixel pull; with ∇S in
// the Jacobian the error here was ≈ 3 σ).
TEST(ImageCorrelation, NoisyShiftWithinItsCovariance) {
    std::mt19937_64 rng(42);
    std::normal_distribution<double> noise(0.0, 0.05);
    int within = 0, trials = 20;
    for (int t = 0; t < trials; ++t) {
        Image templ = sample(kT, kT, 0.0, 0.0, 1.0, 0.0);
        const double sx = -1.3 + 0.17 * t, sy = 0.9 - 0.11 * t;
        Image search = sample(kS, kS, kO + sx, kO + sy, 1.0, 0.0);
        templ.value += templ.value.unaryExpr([&](double) { return noise(rng); });
        search.value += search.value.unaryExpr([&](double) { return noise(rng); });
        CorrelationParameters p;
        p.search_radius = 4;
        const CorrelationResult r = correlate_template(templ, search, {kO, kO}, p);
        ASSERT_TRUE(r.found);
        EXPECT_NEAR(r.shift.x(), sx, 0.05);
        EXPECT_NEAR(r.shift.y(), sy, 0.05);
        const double sdx = std::sqrt(r.covariance(0, 0)), sdy = std::sqrt(r.covariance(1, 1));
        EXPECT_GT(sdx, 0.0);
        if (std::abs(r.shift.x() - sx) < 2.0 * sdx && std::abs(r.shift.y() - sy) < 2.0 * sdy) {
            ++within;
        }
    }
    EXPECT_GE(within, 17);
}

TEST(ImageCorrelation, MaskedPixelsAreLeftOut) {
    const Image templ = sample(kT, kT, 0.0, 0.0, 1.0, 0.0);
    Image search = sample(kS, kS, kO + 0.6, kO - 1.2, 1.0, 0.0);
    // A blob of garbage, masked.
    search.valid.block(20, 25, 8, 8).setConstant(false);
    search.value.block(20, 25, 8, 8).setConstant(1e6);
    CorrelationParameters p;
    p.min_overlap = 0.8;
    const CorrelationResult r = correlate_template(templ, search, {kO, kO}, p);
    ASSERT_TRUE(r.found);
    EXPECT_NEAR(r.shift.x(), 0.6, 0.005);
    EXPECT_NEAR(r.shift.y(), -1.2, 0.005);
}

TEST(ImageCorrelation, ShiftBeyondTheSearchRangeIsNotFound) {
    const Image templ = sample(kT, kT, 0.0, 0.0, 1.0, 0.0);
    const Image search = sample(kS, kS, kO + 6.2, kO, 1.0, 0.0);
    CorrelationParameters p;
    p.search_radius = 3;
    EXPECT_FALSE(correlate_template(templ, search, {kO, kO}, p).found);
    p.search_radius = -1;
    EXPECT_THROW(correlate_template(templ, search, {kO, kO}, p), Error);
}

}  // namespace
}  // namespace tlsmon::test
