// A zone's median over its area from its patches (algorithms/patches/zone_median.hpp) and the
// sampling variance of a median whose members hold several values erring together
// (algorithms/m3c2/zone_uncertainty.hpp): a face of patches in rows 1 m apart with a strip of
// small patches at its upper edge, its change growing up the face; the areal median against
// the change over the area, where the patches' own median is half a row off; its σ against
// the spread of its error over many draws of the patches' noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/m3c2/zone_uncertainty.hpp"
#include "algorithms/patches/zone_median.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::patches {
namespace {

constexpr double kCell = 0.1;  // m

// A patch over x ∈ [x0, x1], z ∈ [z0, z1] of the face y = 0, its cells kCell square, its
// distance the change at the cells' centroid plus `error`.
PatchChange rectangle(double x0, double x1, double z0, double z1, double gradient, double error,
                      double sigma) {
    PatchChange p;
    p.at = Eigen::Vector3d(0.5 * (x0 + x1), 0, 0.5 * (z0 + z1));
    for (double z = z0 + kCell / 2; z < z1; z += kCell)
        for (double x = x0 + kCell / 2; x < x1; x += kCell) p.cells.emplace_back(x, 0, z);
    p.distance = gradient * (p.at.z() - 30) + error;
    p.sampling_sigma = sigma;
    return p;
}

// 10 rows of 16 patches 0.5 m × 1 m over z 30–40 m, and a strip of 7 patches 0.3 m tall at
// the top: 82.4 m², the change g·(z − 30).
std::vector<PatchChange> face(double gradient, double sigma, std::mt19937_64* rng = nullptr) {
    std::normal_distribution<double> noise(0.0, sigma);
    const auto e = [&] { return rng ? noise(*rng) : 0.0; };
    std::vector<PatchChange> out;
    for (int row = 0; row < 10; ++row)
        for (int col = 0; col < 16; ++col)
            out.push_back(rectangle(0.5 * col, 0.5 * (col + 1), 30.0 + row, 31.0 + row, gradient,
                                    e(), sigma));
    for (int col = 0; col < 7; ++col)
        out.push_back(
            rectangle(8.0 * col / 7, 8.0 * (col + 1) / 7, 40.0, 40.3, gradient, e(), sigma));
    return out;
}

TEST(PatchZoneMedian, IsTheMedianOverTheAreaWhereThePatchesMedianStepsBetweenRows) {
    const double g = 2e-4;  // m per m: rows 0.2 mm apart
    const auto patches = face(g, 5e-5);
    const ArealMedian areal = areal_median(patches);
    // Half the area, 41.2 m², lies below z = 35.15 m.
    const double truth = g * 5.15;
    EXPECT_NEAR(areal.value, truth, g * kCell / 2);
    EXPECT_NEAR(areal.gradient.z(), g, 1e-12);
    EXPECT_NEAR(areal.gradient.x(), 0, 1e-12);
    EXPECT_EQ(areal.gradient.y(), 0);                         // the face's normal: not spanned
    EXPECT_EQ(areal.cells, 16u * 10u * 50u + 7u * 11u * 3u);  // 0.5 m × 1 m; 1.14 m × 0.3 m
    // The patches' own median: the 84th of 167 values, in the sixth row, 0.07 mm high.
    std::vector<double> d;
    for (const auto& p : patches) d.push_back(p.distance);
    EXPECT_NEAR(median(d), g * 5.5, 1e-12);
    // Its σ: the patches' values are rows far apart against their σ: the middle patch decides
    // (its cells span a row's change, 4σ, so the count's slope is small but not nil).
    EXPECT_GT(areal.sampling_variance, std::numbers::pi / 2 * 2.5e-9 / 167);
    EXPECT_LE(areal.sampling_variance, 2.5e-9 + 1e-20);
}

TEST(PatchZoneMedian, APatchThatMovedAloneDoesNotTiltTheGradient) {
    auto patches = face(2e-4, 5e-5);
    patches[17].distance += 0.05;  // 5 cm
    const ArealMedian areal = areal_median(patches);
    EXPECT_NEAR(areal.gradient.z(), 2e-4, 1e-12);
    EXPECT_NEAR(areal.value, 2e-4 * 5.15, 2e-4 * kCell);
    EXPECT_TRUE(std::isnan(areal_median({}).value));
    patches[3].distance = NAN;
    EXPECT_THROW(areal_median(patches), Error);
}

TEST(MedianSamplingVarianceOfMembers, OneValueEachIsTheFormForSingleValues) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> z(0.0, 1e-3);
    std::uniform_real_distribution<double> s(1e-4, 1e-3);
    for (int trial = 0; trial < 20; ++trial) {
        const std::size_t n = 1 + std::size_t(trial) * 7;
        std::vector<double> d(n), sigma(n);
        std::vector<std::size_t> first(n + 1);
        for (std::size_t i = 0; i < n; ++i) d[i] = z(rng), sigma[i] = s(rng), first[i + 1] = i + 1;
        EXPECT_DOUBLE_EQ(m3c2::median_sampling_variance(d, first, sigma),
                         m3c2::median_sampling_variance(d, sigma));
    }
}

TEST(MedianSamplingVarianceOfMembers, WorkedByHand) {
    // Two members of 3 and 1 values, all at the median: the count is 3·1[e₁ ≤ 0] + 1[e₂ ≤ 0],
    // var 9/4 + 1/4; the density (3 + 1)·φ(0)/(κσ): below the form for equal values,
    // π/2 · (9 + 1)σ²/16, which it is.
    const std::vector<double> d(4, 0.0), sigma{1e-3, 1e-3};
    const std::vector<std::size_t> first{0, 3, 4};
    EXPECT_NEAR(m3c2::median_sampling_variance(d, first, sigma), std::numbers::pi / 2 * 10e-6 / 16,
                1e-18);
    // Members far apart: the middle value's member alone, σ², above the floor
    // π/2 · (4 + 9·4 + 4)σ²/49.
    const std::vector<double> apart{-1, -1, 0, 0, 0, 1, 1}, s3{1e-3, 2e-3, 1e-3};
    const std::vector<std::size_t> f3{0, 2, 5, 7};
    EXPECT_NEAR(m3c2::median_sampling_variance(apart, f3, s3), 4e-6, 1e-18);
    // The middle two values in different members: (σ_a² + σ_b²)/4, above the floor.
    const std::vector<double> two{-1, 1}, s2{1e-3, 2e-3};
    const std::vector<std::size_t> f2{0, 1, 2};
    EXPECT_NEAR(m3c2::median_sampling_variance(two, f2, s2),
                std::max(5e-6 / 4, std::numbers::pi / 2 * 5e-6 / 4), 1e-18);
    EXPECT_THROW(m3c2::median_sampling_variance(two, std::vector<std::size_t>{0, 2, 1}, s2), Error);
    EXPECT_THROW(m3c2::median_sampling_variance(two, std::vector<std::size_t>{0, 2}, s2), Error);
}

// The areal median's error over 800 draws of the patches' noise (σ 0.1 mm each, common to
// a patch's cells) against its σ, for rows 0, 1, 4 and 20 σ apart: the estimate's RMS over
// the error's 0.99, 0.89, 1.02 and 1.01. With the single values' kernel κσ for every patch
// it was 0.99, 0.88, 0.86 and 0.88: a patch whose cells spread over more than its σ counts in
// proportion to its error where it straddles the median (zone_uncertainty.hpp). Within −15 %
// and +15 %.
TEST(MedianSamplingVarianceOfMembers, FollowsTheArealMediansTrueSigma) {
    constexpr int trials = 800;
    const double sigma = 1e-4;
    std::mt19937_64 rng(29);
    for (const double step : {0.0, 1.0, 4.0, 20.0}) {
        const double g = step * sigma;  // per m: rows 1 m apart
        const double truth = areal_median(face(g, sigma)).value;
        double error2 = 0, estimate = 0;
        for (int k = 0; k < trials; ++k) {
            const ArealMedian a = areal_median(face(g, sigma, &rng));
            error2 += (a.value - truth) * (a.value - truth) / trials;
            estimate += a.sampling_variance / trials;
        }
        const double ratio = std::sqrt(estimate / error2);
        std::printf("rows %.0f σ apart: true σ %.4f mm, estimate / true %.3f\n", step,
                    1e3 * std::sqrt(error2), ratio);
        EXPECT_GT(ratio, 0.85) << "rows " << step << " σ apart";
        EXPECT_LT(ratio, 1.15) << "rows " << step << " σ apart";
    }
}

}  // namespace
}  // namespace tlsmon::patches
