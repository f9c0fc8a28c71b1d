// The dashboard's min/max decimation (daemon/http/series_decimation.hpp) against answers
// worked out by hand.
#include <gtest/gtest.h>

#include <algorithm>

#include "daemon/http/series_decimation.hpp"

namespace tlsmon {
namespace {

TEST(SeriesDecimation, FewPointsAreAllKept) {
    const std::vector<std::int64_t> t{0, 10, 20, 30};
    const std::vector<double> v{1, 2, 3, 4};
    EXPECT_EQ(min_max_decimation(t, v, 0, 30, 2), (std::vector<std::size_t>{0, 1, 2, 3}));
    EXPECT_EQ(min_max_decimation(t, v, 0, 30, 0).size(), 4u);  // 0 buckets: every point
}

TEST(SeriesDecimation, EachBucketKeepsItsLowestAndHighestInTimeOrder) {
    // Ten points over [0, 100), two buckets of 50 s: bucket 0 = t 0..40, bucket 1 = 50..90.
    std::vector<std::int64_t> t;
    for (int i = 0; i < 10; ++i) t.push_back(10 * i);
    const std::vector<double> v{5, 7, 1, 6, 5, 4, 4, 9, 4, 2};
    // bucket 0: low 1 at index 2, high 7 at index 1; bucket 1: high 9 at 7, low 2 at 9.
    EXPECT_EQ(min_max_decimation(t, v, 0, 100, 2), (std::vector<std::size_t>{1, 2, 7, 9}));
}

TEST(SeriesDecimation, AOneEpochSpikeSurvivesAYearAtChartWidth) {
    // A year of 15-minute epochs, flat but for one epoch: 800 pixels keep the spike.
    const std::int64_t n = 365 * 96;
    std::vector<std::int64_t> t(static_cast<std::size_t>(n));
    std::vector<double> v(static_cast<std::size_t>(n), 0.001);
    for (std::int64_t i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = 900 * i;
    v[20000] = 0.025;
    const auto kept = min_max_decimation(t, v, 0, 900 * (n - 1), 800);
    EXPECT_LE(kept.size(), 1600u);
    EXPECT_GE(kept.size(), 800u);
    EXPECT_NE(std::find(kept.begin(), kept.end(), 20000u), kept.end());
    for (std::size_t i = 1; i < kept.size(); ++i) EXPECT_LT(kept[i - 1], kept[i]);
}

TEST(SeriesDecimation, TimesOutsideTheWindowFallIntoTheEndBuckets) {
    const std::vector<std::int64_t> t{-50, 0, 10, 20, 200};
    const std::vector<double> v{3, 1, 2, 0, 8};
    // 2 buckets over [0, 20]: bucket 0 takes -50 (clamped) and 0 -> high 3 (0), low 1 (1);
    // bucket 1 takes 10, 20 and 200 (clamped) -> low 0 (3), high 8 (4).
    EXPECT_EQ(min_max_decimation(t, v, 0, 20, 2), (std::vector<std::size_t>{0, 1, 3, 4}));
}

}  // namespace
}  // namespace tlsmon
