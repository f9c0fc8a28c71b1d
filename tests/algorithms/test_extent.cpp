// Known answers for the extent kernel: a box from its corner points, the share of a cloud
// inside it with and without a margin, boundaries included.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/extent.hpp"

namespace tlsmon::test {
namespace {

TEST(Extent, BoundingBoxOfPointsIsTheirComponentwiseMinAndMax) {
    const std::vector<Eigen::Vector3d> points{{1, -2, 3}, {-4, 5, 0.5}, {2, 0, -6}};
    const BoundingBox box = bounding_box(points);
    EXPECT_EQ(box.min, Eigen::Vector3d(-4, -2, -6));
    EXPECT_EQ(box.max, Eigen::Vector3d(2, 5, 3));
    EXPECT_FALSE(box.empty());
    EXPECT_TRUE(bounding_box({}).empty());
}

TEST(Extent, ShareInsideCountsTheBoundaryAndHonoursTheMargin) {
    BoundingBox box;
    box.extend({0, 0, 0});
    box.extend({10, 10, 10});
    // 2 inside, 1 exactly on the face, 1 at 0.5 outside, 1 at 2 outside.
    const std::vector<Eigen::Vector3d> points{
        {5, 5, 5}, {1, 9, 2}, {10, 5, 5}, {10.5, 5, 5}, {5, -2, 5}};
    EXPECT_DOUBLE_EQ(share_inside(points, box, 0.0), 3.0 / 5.0);
    EXPECT_DOUBLE_EQ(share_inside(points, box, 0.5), 4.0 / 5.0);
    EXPECT_DOUBLE_EQ(share_inside(points, box, 2.0), 1.0);
    EXPECT_TRUE(std::isnan(share_inside({}, box, 1.0)));
}

}  // namespace
}  // namespace tlsmon::test
