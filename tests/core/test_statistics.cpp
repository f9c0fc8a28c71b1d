#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/statistics.hpp"

namespace tlsmon {
namespace {

TEST(Statistics, QuantilesInterpolateBetweenOrderStatistics) {
    const std::vector<double> sorted = {1.0, 2.0, 4.0, 8.0};
    // Position (n − 1)·q = 0.75, 1.5, 2.25: R's quantile(type = 7) of the same values.
    EXPECT_DOUBLE_EQ(quantile_of_sorted(sorted, 0.25), 1.75);
    EXPECT_DOUBLE_EQ(quantile_of_sorted(sorted, 0.5), 3.0);
    EXPECT_DOUBLE_EQ(quantile_of_sorted(sorted, 0.75), 5.0);
    EXPECT_DOUBLE_EQ(quantile_of_sorted(sorted, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(quantile_of_sorted(sorted, 1.0), 8.0);
    EXPECT_TRUE(std::isnan(quantile_of_sorted({}, 0.5)));
}

TEST(Statistics, MedianOfOddAndEvenCounts) {
    EXPECT_DOUBLE_EQ(median({5.0, 1.0, 3.0}), 3.0);
    EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
    EXPECT_DOUBLE_EQ(median_high({4.0, 1.0, 3.0, 2.0}), 3.0);
    EXPECT_DOUBLE_EQ(median_high({5.0, 1.0, 3.0}), 3.0);
    EXPECT_TRUE(std::isnan(median({})));
    EXPECT_TRUE(std::isnan(median_high({})));
}

TEST(Statistics, MedianGivesTheSameBitsAsTheQuantileAtOneHalf) {
    std::mt19937 random(7);
    std::normal_distribution<double> noise(0.0, 1e-3);
    for (int count : {2, 3, 10, 11, 1000, 1001}) {
        std::vector<double> v(static_cast<std::size_t>(count));
        for (double& x : v) x = 0.1 + noise(random);
        std::vector<double> sorted = v;
        std::sort(sorted.begin(), sorted.end());
        EXPECT_EQ(median(v), quantile_of_sorted(sorted, 0.5)) << count << " values";
    }
}

TEST(Statistics, MedianAbsoluteDeviation) {
    // Median 3; absolute deviations {2, 1, 0, 1, 6}: MAD 1.
    const MedianAndMad m = median_and_mad({1.0, 2.0, 3.0, 4.0, 9.0});
    EXPECT_DOUBLE_EQ(m.median, 3.0);
    EXPECT_DOUBLE_EQ(m.mad, 1.0);
    const MedianAndMad even = median_and_mad({4.0, 1.0, 2.0, 3.0});  // |x − 2.5|: .5 .5 1.5 1.5
    EXPECT_DOUBLE_EQ(even.median, 2.5);
    EXPECT_DOUBLE_EQ(even.mad, 1.0);
    // For normal values σ ≈ 1.4826·MAD.
    std::mt19937 random(11);
    std::normal_distribution<double> noise(0.0, 2.0);
    std::vector<double> v(200000);
    for (double& x : v) x = noise(random);
    EXPECT_NEAR(kMadToSigma * median_and_mad(v).mad, 2.0, 0.02);
    const MedianAndMad none = median_and_mad({});
    EXPECT_TRUE(std::isnan(none.median));
    EXPECT_TRUE(std::isnan(none.mad));
}

}  // namespace
}  // namespace tlsmon
