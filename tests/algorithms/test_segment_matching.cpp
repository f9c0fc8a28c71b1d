// Campaign segments matched to the reference's by where their points land: two walls of a
// corner and the ground in the reference, segmented with other numbers in the campaign; a
// segment half off the reference's surface keeps its share and no match below min_overlap;
// the result is the same on one thread and on every core.
#include <gtest/gtest.h>

#include <random>

#include "algorithms/campaign/point_grid.hpp"
#include "algorithms/campaign/segment_matching.hpp"

namespace tlsmon::campaign {
namespace {

struct Cloud {
    std::vector<Eigen::Vector3d> points;
    std::vector<std::int32_t> label;
    void add(int n, const std::function<Eigen::Vector3d(double, double)>& at, std::int32_t l,
             std::mt19937& rng) {
        std::uniform_real_distribution<double> u(0, 1);
        for (int i = 0; i < n; ++i) {
            points.push_back(at(u(rng), u(rng)));
            label.push_back(l);
        }
    }
};

// Wall A on x = 0, wall B on y = 0 (5 m long, 3 m high), the ground on z = 0.
Eigen::Vector3d wall_a(double s, double t) {
    return {0, 0.3 + 4.7 * s, 0.3 + 2.7 * t};
}
Eigen::Vector3d wall_b(double s, double t) {
    return {0.3 + 4.7 * s, 0, 0.3 + 2.7 * t};
}
Eigen::Vector3d ground(double s, double t) {
    return {0.3 + 4.7 * s, 0.3 + 4.7 * t, 0};
}

TEST(SegmentMatching, EachSegmentIsTheReferenceSegmentItsPointsLandOn) {
    std::mt19937 rng(5);
    Cloud reference;
    reference.add(20000, wall_a, 4, rng);  // the reference's numbering: A is 4, B is 1
    reference.add(20000, wall_b, 1, rng);
    reference.add(20000, ground, -1, rng);  // ground: no segment
    const PointGrid grid(reference.points, 0.2);
    const auto nearest = [&](const Eigen::Vector3d& x) {
        std::int64_t best = -1;
        double d_best = 0.2 * 0.2;  // within() gives squared distances
        grid.within(x, 0.2, [&](std::uint32_t k, double d) {
            if (d <= d_best) {
                d_best = d;
                best = k;
            }
        });
        return best;
    };
    Cloud campaign;  // its own numbering: B is 0, A is 1
    campaign.add(3000, wall_b, 0, rng);
    campaign.add(3000, wall_a, 1, rng);
    // Segment 2: half on wall A, half 1 m in front of it, where the reference has nothing.
    campaign.add(1000, wall_a, 2, rng);
    campaign.add(
        1000, [](double s, double t) { return Eigen::Vector3d(1.0, 1 + s, 1 + t); }, 2, rng);
    campaign.add(500, ground, 3, rng);  // on the reference's ground only
    const auto m =
        match_segments(campaign.points, campaign.label, 5, nearest, reference.label, 0.6, 5000, 0);
    ASSERT_EQ(m.size(), 5u);
    EXPECT_EQ(m[0].reference, 1);
    EXPECT_EQ(m[0].overlap, 1.0);
    EXPECT_EQ(m[0].sampled, 3000u);
    EXPECT_EQ(m[1].reference, 4);
    EXPECT_EQ(m[1].overlap, 1.0);
    EXPECT_EQ(m[2].reference, -1);  // 50 % on A, below min_overlap
    EXPECT_NEAR(m[2].overlap, 0.5, 1e-12);
    EXPECT_EQ(m[3].reference, -1);
    EXPECT_EQ(m[3].overlap, 0.0);
    EXPECT_EQ(m[4].sampled, 0u);  // no points
    // At most `samples` points a segment, taken evenly; the same on one thread.
    const auto few =
        match_segments(campaign.points, campaign.label, 5, nearest, reference.label, 0.4, 100, 1);
    EXPECT_EQ(few[0].sampled, 100u);
    EXPECT_EQ(few[0].reference, 1);
    EXPECT_EQ(few[2].reference, 4);
    EXPECT_NEAR(few[2].overlap, 0.5, 0.06);
    const auto one =
        match_segments(campaign.points, campaign.label, 5, nearest, reference.label, 0.6, 5000, 1);
    for (std::size_t s = 0; s < 5; ++s) {
        EXPECT_EQ(one[s].reference, m[s].reference);
        EXPECT_EQ(one[s].overlap, m[s].overlap);
    }
}

}  // namespace
}  // namespace tlsmon::campaign
