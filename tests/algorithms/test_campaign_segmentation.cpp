// Verticality and the two-stage segmentation of campaign clouds (algorithms/campaign/)
// against known answers: planes of known tilt give V = 1 − |cos tilt| exactly, and with a
// personal scanner's noise still fall in their class; a floor with a wall standing on it and
// a ramp apart give two clusters and three large segments of the expected classes; the mean
// spacing of a regular grid is its step.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/campaign/segmentation.hpp"
#include "algorithms/campaign/verticality.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {
namespace {

// A square of side `size` sampled every `step` on the plane through `origin` spanned by a
// and b, with N(0, noise) added along the plane's normal.
void add_plane(std::vector<Eigen::Vector3d>& out, const Eigen::Vector3d& origin,
               const Eigen::Vector3d& a, const Eigen::Vector3d& b, double size_a, double size_b,
               double step, double noise = 0, unsigned seed = 1) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    const Eigen::Vector3d n = a.cross(b).normalized();
    for (double s = 0; s <= size_a + 1e-9; s += step)
        for (double t = 0; t <= size_b + 1e-9; t += step)
            out.push_back(origin + s * a + t * b + (noise > 0 ? noise * n01(rng) : 0.0) * n);
}

TEST(CampaignVerticality, APlaneOfKnownTiltGivesOneMinusTheCosineOfItsTilt) {
    for (const double tilt_deg : {0.0, 30.0, 60.0, 90.0}) {
        // A plane whose normal is tilted by `tilt` from vertical: V = 1 − cos(tilt).
        const double t = tilt_deg * std::numbers::pi / 180;
        std::vector<Eigen::Vector3d> cloud;
        add_plane(cloud, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                  Eigen::Vector3d(0, std::cos(t), std::sin(t)), 1.0, 1.0, 0.02);
        const auto v = verticality(cloud, {});
        // A point in the middle (its neighbourhood is a full disc).
        const std::size_t mid = cloud.size() / 2;
        ASSERT_TRUE(std::isfinite(v[mid]));
        EXPECT_NEAR(v[mid], 1 - std::cos(t), 1e-5) << tilt_deg << "°";
    }
}

TEST(CampaignVerticality, WithAPersonalScannersNoiseAWallStaysVerticalAndAFloorHorizontal) {
    // 1 cm noise on 2 cm sampling, the study's 0.10 m radius.
    std::vector<Eigen::Vector3d> wall, floor;
    add_plane(wall, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(),
              2.0, 2.0, 0.02, 0.01, 3);
    add_plane(floor, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
              2.0, 2.0, 0.02, 0.01, 4);
    const VerticalityParameters p;
    const auto share = [&](const std::vector<Eigen::Vector3d>& cloud, VerticalityClass c) {
        const auto v = verticality(cloud, p);
        std::size_t hits = 0;
        for (const float x : v) hits += classify(x, p) == c;
        return double(hits) / double(cloud.size());
    };
    EXPECT_GT(share(wall, VerticalityClass::vertical), 0.99);
    EXPECT_GT(share(floor, VerticalityClass::horizontal), 0.95);
}

TEST(CampaignVerticality, TooFewNeighboursIsUndefinedAndBadParametersAreRefused) {
    const std::vector<Eigen::Vector3d> sparse = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const auto v = verticality(sparse, {});
    EXPECT_FALSE(std::isfinite(v[0]));
    EXPECT_EQ(classify(v[0], {}), VerticalityClass::undefined);
    VerticalityParameters p;
    p.vertical_min = 0.01;  // below horizontal_max
    EXPECT_THROW(verticality(sparse, p), Error);
}

TEST(CampaignSegmentation, TheMeanSpacingOfARegularGridIsItsStep) {
    std::vector<Eigen::Vector3d> cloud;
    add_plane(cloud, Eigen::Vector3d(5, 3, 1), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
              1.0, 1.0, 0.025);
    EXPECT_NEAR(mean_spacing(cloud, 1000), 0.025, 1e-9);
}

TEST(CampaignSegmentation, AWallOnAFloorAndARampApartGiveTheirSegments) {
    // A floor 3 × 3 m, a wall 3 m long and 2 m high standing on its middle, and a 45° ramp
    // 1 m beyond the floor's edge; 2 cm sampling, 5 mm noise.
    std::vector<Eigen::Vector3d> cloud;
    add_plane(cloud, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
              3.0, 3.0, 0.02, 0.005, 5);
    const std::size_t floor_end = cloud.size();
    add_plane(cloud, Eigen::Vector3d(0, 1.5, 0.02), Eigen::Vector3d::UnitX(),
              Eigen::Vector3d::UnitZ(), 3.0, 2.0, 0.02, 0.005, 6);
    const std::size_t wall_end = cloud.size();
    add_plane(cloud, Eigen::Vector3d(4.0, 0, 0), Eigen::Vector3d::UnitY(),
              Eigen::Vector3d(1, 0, 1).normalized(), 3.0, 1.5, 0.02, 0.005, 7);
    const VerticalityParameters vp;
    const auto v = verticality(cloud, vp);
    std::vector<VerticalityClass> classes;
    for (const float x : v) classes.push_back(classify(x, vp));
    const Segmentation s = segment_cloud(cloud, classes, {}, 2);
    EXPECT_EQ(segment_cloud(cloud, classes, {}, 1).segment, s.segment)
        << "the same segments on one thread";

    EXPECT_NEAR(s.spacing, 0.02, 0.004);
    EXPECT_NEAR(s.distance, 3 * s.spacing, 1e-12);
    EXPECT_EQ(s.clusters, 2u) << "the floor with its wall, and the ramp";
    EXPECT_EQ(s.cluster[0], s.cluster[floor_end]);
    EXPECT_NE(s.cluster[0], s.cluster[wall_end]);
    // The large segments: the floor's two halves (the wall's foot, of class "other", parts
    // them), the wall and the ramp.
    std::map<VerticalityClass, std::size_t> large;  // class -> points in segments > 2000
    for (const auto& g : s.segments)
        if (g.points > 2000) large[g.kind] += g.points;
    ASSERT_EQ(large.size(), 3u);
    // Most of each surface in its class's segments: the floor away from the wall's foot, the
    // wall above its foot, the ramp.
    EXPECT_GT(large[VerticalityClass::horizontal], 0.9 * double(floor_end));
    EXPECT_GT(large[VerticalityClass::vertical], 0.9 * double(wall_end - floor_end));
    EXPECT_GT(large[VerticalityClass::other], 0.95 * double(cloud.size() - wall_end));
    // A segment lies in one cluster and holds one class.
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        const auto k = s.segment[i];
        if (k < 0) continue;
        EXPECT_EQ(s.segments[std::size_t(k)].cluster, s.cluster[i]);
        EXPECT_EQ(s.segments[std::size_t(k)].kind,
                  classes[i] == VerticalityClass::undefined ? VerticalityClass::other : classes[i]);
    }
}

}  // namespace
}  // namespace tlsmon::campaign
