// The σ of a zone's mean and median M3C2 distance (algorithms/m3c2/zone_uncertainty.hpp): a
// case worked by hand, and 4000 simulated zones whose core distances err by their own
// sampling σ and one shared registration error — the 95 % interval 1.96 σ covers the mean's
// and the median's true error at 95 % (within the binomial 99.9 % band), where one core
// point's LoD95, the rows' earlier uncertainty, covers nearly always.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/m3c2/zone_uncertainty.hpp"
#include "core/error.hpp"

namespace tlsmon::m3c2 {
namespace {

TEST(M3c2ZoneUncertainty, WorkedByHand) {
    // 100 core points, σ_s 1 mm each, σ_reg 0.2 mm; r = s = 0.5 m: k = π.
    const std::vector<double> s(100, 0.001), reg(100, 0.0002);
    const ZoneUncertainty u = zone_uncertainty(s, reg, 0.5, 0.5);
    EXPECT_NEAR(u.overlap, std::numbers::pi, 1e-12);
    EXPECT_NEAR(u.sampling_mean, std::sqrt(std::numbers::pi * 1e-6 / 100), 1e-15);
    EXPECT_NEAR(u.registration, 0.0002, 1e-15);
    EXPECT_NEAR(u.mean_sigma, std::sqrt(std::numbers::pi * 1e-8 + 4e-8), 1e-15);
    EXPECT_NEAR(u.median_sigma, std::sqrt(std::numbers::pi / 2 * std::numbers::pi * 1e-8 + 4e-8),
                1e-15);
    // Cylinders that do not overlap: k = 1.
    EXPECT_DOUBLE_EQ(zone_uncertainty(s, reg, 0.5, 2.0).overlap, 1.0);
    // No core point: zero, not NaN.
    EXPECT_EQ(zone_uncertainty({}, {}, 0.5, 0.5).n, 0u);
    // Mistakes.
    EXPECT_THROW(zone_uncertainty(s, std::vector<double>(3, 0.0), 0.5, 0.5), Error);
    EXPECT_THROW(zone_uncertainty(s, reg, 0.0, 0.5), Error);
    std::vector<double> bad = s;
    bad[7] = -1;
    EXPECT_THROW(zone_uncertainty(bad, reg, 0.5, 0.5), Error);
}

TEST(M3c2ZoneUncertainty, CoversTheZonesTrueErrorAtItsNominalRate) {
    constexpr int trials = 4000, n = 150;
    std::mt19937_64 rng(11);
    std::normal_distribution<double> z(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0005, 0.002);
    int mean_within = 0, median_within = 0, point_lod_within = 0;
    for (int t = 0; t < trials; ++t) {
        // Independent cylinders (spacing 2r), σ_s between 0.5 and 2 mm, σ_reg 0.15 mm.
        std::vector<double> s(n), reg(n, 0.00015), d(n);
        const double shared = 0.00015 * z(rng);
        double point_lod = 0;
        for (int i = 0; i < n; ++i) {
            s[static_cast<std::size_t>(i)] = u(rng);
            d[static_cast<std::size_t>(i)] = shared + s[static_cast<std::size_t>(i)] * z(rng);
            point_lod += 1.96 * (s[static_cast<std::size_t>(i)] + 0.00015) / n;
        }
        const ZoneUncertainty zu = zone_uncertainty(s, reg, 0.5, 1.0);
        double mean = 0;
        for (double v : d) mean += v / n;
        std::nth_element(d.begin(), d.begin() + n / 2, d.end());
        const double median = d[n / 2];
        mean_within += std::abs(mean) <= 1.96 * zu.mean_sigma;
        median_within += std::abs(median) <= 1.96 * zu.median_sigma;
        point_lod_within += std::abs(median) <= point_lod;
    }
    const double band = 3.3 * std::sqrt(0.95 * 0.05 / trials);
    const double mean_share = double(mean_within) / trials;
    const double median_share = double(median_within) / trials;
    const double point_share = double(point_lod_within) / trials;
    std::printf("within 1.96 sigma: mean %.3f, median %.3f; within one core point's LoD95 %.3f\n",
                mean_share, median_share, point_share);
    EXPECT_NEAR(mean_share, 0.95, band);
    // The median's √(π/2) holds for equal σ; with σ_s varying 4× it is slightly cautious.
    EXPECT_NEAR(median_share, 0.95, 2 * band);
    EXPECT_GT(point_share, 0.999);  // the padding the zone σ removes
}

}  // namespace
}  // namespace tlsmon::m3c2
