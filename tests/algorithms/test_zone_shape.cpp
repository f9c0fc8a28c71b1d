// Zone shapes: boxes, prisms (point in polygon with its boundary) and bands, on constructed
// cases whose answers are known by construction.
#include <gtest/gtest.h>

#include "algorithms/zones/zone_shape.hpp"
#include "core/error.hpp"

namespace tlsmon {
namespace {

TEST(ZoneShape, PolygonInsideOutsideAndBoundary) {
    // An L: the unit squares (0..2, 0..1) and (0..1, 1..2), clockwise.
    const std::vector<Eigen::Vector2d> l{{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}};
    EXPECT_TRUE(inside_polygon(l, {0.5, 1.5}));
    EXPECT_TRUE(inside_polygon(l, {1.5, 0.5}));
    EXPECT_FALSE(inside_polygon(l, {1.5, 1.5}));  // the notch
    EXPECT_TRUE(inside_polygon(l, {1.0, 1.5}));   // on an edge
    EXPECT_TRUE(inside_polygon(l, {1.0, 1.0}));   // on the reflex vertex
    EXPECT_TRUE(inside_polygon(l, {2.0, 0.0}));   // on a vertex
    EXPECT_FALSE(inside_polygon(l, {2.0 + 1e-9, 0.5}));
    EXPECT_FALSE(inside_polygon(l, {-0.5, 1.0}));  // level with a vertex, outside
}

TEST(ZoneShape, PrismNeedsItsZRangeAndPolygon) {
    const ZoneShape p = prism_zone("p", {{0, 0}, {4, 0}, {0, 4}}, 1.0, 3.0);
    EXPECT_EQ(p.bounds().min(), Eigen::Vector3d(0, 0, 1));
    EXPECT_EQ(p.bounds().max(), Eigen::Vector3d(4, 4, 3));
    EXPECT_TRUE(p.contains({1, 1, 1}));
    EXPECT_TRUE(p.contains({2, 2, 3}));  // on the hypotenuse, at the top
    EXPECT_FALSE(p.contains({2.5, 2, 2}));
    EXPECT_FALSE(p.contains({1, 1, 3.5}));
    EXPECT_THROW(prism_zone("q", {{0, 0}, {1, 1}, {2, 2}}, 0, 1), Error);
    EXPECT_THROW(prism_zone("q", {{0, 0}, {1, 0}, {0, 1}}, 1, 1), Error);
}

TEST(ZoneShape, BandsCutTheZoneAndAreNamedByTheirLimits) {
    const ZoneShape face = box_zone("face", {0, 0, 0.5}, {10, 1, 39});
    const auto bands = bands_of(face, 2, 10.0, 0.0, 40.0);
    ASSERT_EQ(bands.size(), 4u);
    EXPECT_EQ(bands[0].name, "face 0–10 m");
    EXPECT_EQ(bands[3].name, "face 30–40 m");
    EXPECT_EQ(bands[0].box.min().z(), 0.5);  // within the zone
    EXPECT_EQ(bands[3].box.max().z(), 39.0);
    EXPECT_EQ(bands[1].box.min().z(), 10.0);
    EXPECT_EQ(bands[1].box.max().z(), 20.0);
    const auto halves = bands_of(face, 0, 2.5, 5.0, 10.0);
    ASSERT_EQ(halves.size(), 2u);
    EXPECT_EQ(halves[1].name, "face 7.5–10 m");
    // Bands beyond the zone are left out; none at all is an error.
    EXPECT_EQ(bands_of(face, 2, 10.0, -20.0, 20.0).size(), 2u);
    EXPECT_THROW(bands_of(face, 2, 10.0, 50.0, 60.0), Error);
    EXPECT_THROW(bands_of(face, 2, 0.0, 0.0, 10.0), Error);
}

}  // namespace
}  // namespace tlsmon
