// Voxel thinning of campaign clouds (algorithms/campaign/thinning.hpp) against known answers:
// a regular grid finer than the voxel keeps one point per voxel, the first in the cloud's
// order; every point knows its voxel; flags leave points out; the result does not depend on
// the thread count; and a noisy plane thinned is biased by its place in the voxel grid, which
// is why the registrations do not use the thinned points.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "algorithms/campaign/thinning.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {
namespace {

TEST(CampaignThinning, AGridFinerThanTheVoxelKeepsTheFirstPointOfEachVoxel) {
    // 0.01 m grid over [0.005, 0.995]² at z = 0.5: 100 × 100 points, 0.05 m voxels hold 5 × 5.
    std::vector<Eigen::Vector3d> cloud;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j) cloud.emplace_back(0.005 + 0.01 * i, 0.005 + 0.01 * j, 0.5);
    const VoxelThinning t = thin_by_voxel(cloud, 0.05, {}, 2);
    ASSERT_EQ(t.voxels(), 400u);
    std::set<std::size_t> kept(t.kept.begin(), t.kept.end());
    for (std::size_t k = 0; k < cloud.size(); ++k) {
        const int i = int(k / 100), j = int(k % 100);
        // The first point of its voxel in the cloud's order: i and j both multiples of 5.
        EXPECT_EQ(kept.count(k), (i % 5 == 0 && j % 5 == 0) ? 1u : 0u) << i << "," << j;
        // Its voxel's kept point is the one at the voxel's lower corner.
        const std::size_t first = std::size_t(i / 5 * 5 * 100 + j / 5 * 5);
        ASSERT_LT(t.of[k], t.voxels());
        EXPECT_EQ(t.kept[t.of[k]], first);
    }
    EXPECT_EQ(kept_points(cloud, t).size(), 400u);
}

TEST(CampaignThinning, FlagsAndNonFinitePointsAreLeftOutAndZeroKeepsEveryPoint) {
    std::vector<Eigen::Vector3d> cloud = {
        {0.01, 0.01, 0.01}, {0.02, 0.02, 0.02}, {0.5, 0.5, 0.5}, {0.51, 0.5, 0.5}};
    cloud.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0, 0);
    const std::vector<std::uint8_t> take = {0, 1, 1, 1, 1};
    const VoxelThinning t = thin_by_voxel(cloud, 0.1, take, 1);
    ASSERT_EQ(t.voxels(), 2u);
    EXPECT_EQ(t.of[0], VoxelThinning::kNone);  // not taken
    EXPECT_EQ(t.of[4], VoxelThinning::kNone);  // not finite
    EXPECT_EQ(t.kept[t.of[1]], 1u);            // the first taken point of the first voxel
    EXPECT_EQ(t.kept[t.of[3]], 2u);
    EXPECT_EQ(t.of[2], t.of[3]);

    const VoxelThinning all = thin_by_voxel(cloud, 0.0, {}, 1);
    EXPECT_EQ(all.voxels(), 4u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(all.kept[all.of[i]], i);

    EXPECT_THROW(thin_by_voxel(cloud, -0.1), Error);
    EXPECT_THROW(thin_by_voxel(cloud, 0.1, std::vector<std::uint8_t>(2, 1)), Error);
}

TEST(CampaignThinning, TheThreadsDoNotMatterButANoisyPlaneThinnedIsBiasedByItsPlaceInTheGrid) {
    // Why a registration does not use the voxel-thinned points: a plane z = a with 20 mm noise,
    // 400 000 points on 9 m², thinned at 0.03 m. With the plane on a voxel boundary (a = 0)
    // or mid-voxel (a = 0.015) the kept points' mean height is the plane's; a quarter of the
    // way (a = 0.0075) it is not, by about 1 mm — far beyond the kept points' standard error.
    const auto bias = [](double a, unsigned threads, VoxelThinning* out = nullptr) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(0.0, 3.0);
        std::normal_distribution<double> noise(0.0, 0.020);
        std::vector<Eigen::Vector3d> cloud(400000);
        for (auto& p : cloud) p = {u(rng), u(rng), a + noise(rng)};
        VoxelThinning t = thin_by_voxel(cloud, 0.03, {}, threads);
        double mean = 0;
        for (const auto i : t.kept) mean += cloud[i].z();
        mean /= double(t.voxels());
        if (out) *out = std::move(t);
        return mean - a;
    };
    VoxelThinning one, two;
    EXPECT_EQ(bias(0.0075, 1, &one), bias(0.0075, 2, &two));
    EXPECT_EQ(one.kept, two.kept);
    EXPECT_EQ(one.of, two.of);
    const double standard_error = 0.020 / std::sqrt(double(one.voxels()));  // ≈ 0.1 mm
    EXPECT_LT(std::abs(bias(0.0, 2)), 3 * standard_error);
    EXPECT_LT(std::abs(bias(0.015, 2)), 3 * standard_error);
    EXPECT_LT(bias(0.0075, 2), -0.0006);
    EXPECT_GT(bias(0.0225, 2), 0.0006);
}

}  // namespace
}  // namespace tlsmon::campaign
