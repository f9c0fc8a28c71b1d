// An epoch that saw only part of a cylinder (algorithms/m3c2/distance.hpp, partly_seen): on
// relief the mean over half the disc is not the mean over all of it, which no σ holds; such a
// core point gives no distance, while one seen whole, at another density or sparsely, does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "algorithms/m3c2/reference.hpp"

namespace tlsmon::test {
namespace {

using Eigen::Vector3d;
using namespace tlsmon::m3c2;

// A horizontal ground with relief (±1 cm over 0.8 by 1.1 m: a stone, a hollow), raised by `z`,
// sampled every `step` where x >= x_min, with 0.5 mm of noise.
std::vector<Vector3d> relief(double z, double step, double x_min, unsigned seed) {
    std::mt19937_64 random(seed);
    std::normal_distribution<double> noise(0.0, 0.0005);
    std::vector<Vector3d> points;
    for (double x = -0.6; x <= 0.6; x += step)
        for (double y = -0.6; y <= 0.6; y += step) {
            if (x < x_min) continue;
            const double h =
                0.01 * std::sin(2 * M_PI * x / 0.8 + 0.4) * std::cos(2 * M_PI * y / 1.1);
            points.emplace_back(x, y, z + h + noise(random));
        }
    return points;
}

TEST(M3c2PartlySeen, HalfACylinderOnReliefGivesNoDistanceAWholeOneDoes) {
    const auto reference_cloud = relief(0.0, 0.01, -1.0, 1);
    const Reference r = prepare_reference(reference_cloud, {Vector3d::Zero()},
                                          {{0.5}, Orientation::along({0, 0, 1})},
                                          {0.5, 0.1, CylinderStatistic::mean});
    const DistanceParameters p{10, 0.0};
    // Seen whole, raised 2 mm: the distance, within its LoD.
    const auto whole = cylinder_sides(r.cylinders, relief(0.002, 0.01, -1.0, 2));
    const Distance d = distance_between(r.reference_side[0], whole[0], p);
    ASSERT_TRUE(std::isfinite(d.distance));
    EXPECT_NEAR(d.distance, 0.002, d.lod);
    EXPECT_LT(r.reference_side[0].lateral.norm(), 0.01);
    EXPECT_NEAR(r.reference_side[0].lateral_spread, 0.5 / std::sqrt(2.0), 0.01);
    // Seen at a quarter of the density: still whole.
    const auto coarse = cylinder_sides(r.cylinders, relief(0.002, 0.02, -1.0, 3));
    EXPECT_TRUE(std::isfinite(distance_between(r.reference_side[0], coarse[0], p).distance));
    // Half the disc seen (x >= 0): its mean is off by the relief, far beyond the LoD that the
    // points' spread gives, and the offset across the axis moved by 4R/3π = 0.21 m.
    const auto half = cylinder_sides(r.cylinders, relief(0.002, 0.01, 0.0, 4));
    ASSERT_GE(half[0].count, 10u);
    const double published = half[0].centre - r.reference_side[0].centre;
    const double lod = 1.96 * sampling_sigma(r.reference_side[0], half[0]);
    EXPECT_GT(std::abs(published - 0.002), lod);
    std::printf("half a cylinder on relief: %.2f mm off, LoD95 %.2f mm\n",
                1e3 * (published - 0.002), 1e3 * lod);
    EXPECT_NEAR((half[0].lateral - r.reference_side[0].lateral).norm(), 4 * 0.5 / (3 * M_PI), 0.01);
    EXPECT_TRUE(partly_seen(r.reference_side[0], half[0]));
    EXPECT_TRUE(std::isnan(distance_between(r.reference_side[0], half[0], p).distance));
    // A tenth missing (x >= −0.4): an offset of about 0.05 R, within what is taken as whole.
    const auto most = cylinder_sides(r.cylinders, relief(0.002, 0.01, -0.4, 5));
    EXPECT_FALSE(partly_seen(r.reference_side[0], most[0]));
}

// Sparse cylinders cannot tell a part seen from chance: 12 points drawn at random over the
// disc in each cloud move the offset by about a third of the RMS distance, so no core point
// is refused for it; with 400 points each the same draw is never refused either.
TEST(M3c2PartlySeen, ChanceInASparseCylinderIsNotTakenForAPartSeen) {
    std::mt19937_64 random(9);
    std::uniform_real_distribution<double> at(-0.5, 0.5);
    const auto disc = [&](std::size_t n) {
        std::vector<Vector3d> points;
        while (points.size() < n) {
            const Vector3d p(at(random), at(random), 0.0);
            if (p.head<2>().norm() <= 0.5) points.push_back(p);
        }
        return points;
    };
    int refused = 0, draws = 0;
    for (std::size_t n : {12u, 400u}) {
        for (int k = 0; k < 200; ++k, ++draws) {
            CylinderSide one, two;
            const auto a = disc(n), b = disc(n);
            std::vector<std::uint32_t> members(n);
            for (std::uint32_t i = 0; i < n; ++i) members[i] = i;
            one.count = two.count = static_cast<std::uint32_t>(n);
            set_lateral(one, a, members, Vector3d::Zero(), Vector3d::UnitZ());
            set_lateral(two, b, members, Vector3d::Zero(), Vector3d::UnitZ());
            refused += partly_seen(one, two);
        }
    }
    EXPECT_LE(refused, 2) << "of " << draws;
}

}  // namespace
}  // namespace tlsmon::test
