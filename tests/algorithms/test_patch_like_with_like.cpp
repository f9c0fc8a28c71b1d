// A patch's planes over the part of its footprint both epochs saw alike
// (algorithms/patches/like_with_like.hpp): on relief, an epoch that saw half the footprint is
// compared with the reference's same half, not with its whole plane; seen whole, at another
// density or sparsely, the whole planes are compared as before.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "algorithms/patches/like_with_like.hpp"

namespace tlsmon::patches {
namespace {

// Points of a patch 1 m square in its own frame (u, v in [0, 1)): relief of ±1 cm (a stone, a
// hollow: 0.8 by 1.1 m) raised by `w0`, every `step` where u >= u_min, 0.5 mm of noise.
std::vector<Eigen::Vector3f> relief(double w0, double step, double u_min, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.0005);
    std::vector<Eigen::Vector3f> out;
    for (double u = step / 2; u < 1.0; u += step)
        for (double v = step / 2; v < 1.0; v += step) {
            if (u < u_min) continue;
            const double w =
                w0 + 0.01 * std::sin(2 * M_PI * u / 0.8 + 0.4) * std::cos(2 * M_PI * v / 1.1) +
                noise(rng);
            out.emplace_back(float(u), float(v), float(w));
        }
    return out;
}

std::vector<BlockMoments> blocks_of(const std::vector<Eigen::Vector3f>& uvw, double side) {
    return block_moments(uvw, std::vector<std::uint8_t>(uvw.size(), 1), side);
}

TEST(PatchLikeWithLike, HalfTheFootprintOnReliefIsComparedWithTheSameHalf) {
    const Parameters p;
    const auto reference = relief(0.0, 0.02, -1.0, 1);
    const double side = block_side(1.0, reference.size());
    EXPECT_EQ(side, kBlock);  // 2500 points on 1 m²: 100 a block
    const auto ref_blocks = blocks_of(reference, side);
    ASSERT_EQ(ref_blocks.size(), 25u);
    // The epoch raised 2 mm and seen on u >= 0.4 only: its plane over that part is off by the
    // relief, beyond the LoD.
    const auto half = blocks_of(relief(0.002, 0.02, 0.4, 2), side);
    const PatchResult whole =
        patch_distance(fit_plane(total(ref_blocks)), fit_plane(total(half)), 0.0, p);
    ASSERT_EQ(whole.outcome, PatchOutcome::measured);
    EXPECT_GT(std::abs(whole.distance.distance - 0.002), whole.distance.lod);
    const SeenAlike seen = seen_alike(ref_blocks, half);
    EXPECT_TRUE(seen.partial);
    // The columns of blocks at u from 0.4 are seen; the first of them borders the unseen ones
    // and is left out too: 2 columns of 5 blocks of 100 points.
    EXPECT_EQ(seen.reference.m, 2 * 5 * 100);
    EXPECT_EQ(seen.epoch.m, seen.reference.m);
    const PatchResult like = compared_distance(ref_blocks, half, 0.0, p);
    ASSERT_EQ(like.outcome, PatchOutcome::measured);
    EXPECT_NEAR(like.distance.distance, 0.002, like.distance.lod);
    // It rests on those two columns' fits, and is taken over their centroid (u = 0.8).
    EXPECT_TRUE(like.partial);
    EXPECT_EQ(like.reference.count, 1000u);
    EXPECT_EQ(like.epoch.count, 1000u);
    EXPECT_NEAR(like.reference.centroid.x(), 0.8, 1e-7);  // float32 points
    EXPECT_NEAR(like.reference.centroid.y(), 0.5, 1e-7);
    std::printf(
        "half a patch on relief: whole planes %.2f mm off (LoD95 %.2f mm), like with "
        "like %.3f mm off (LoD95 %.2f mm)\n",
        1e3 * (whole.distance.distance - 0.002), 1e3 * whole.distance.lod,
        1e3 * (like.distance.distance - 0.002), 1e3 * like.distance.lod);
}

TEST(PatchLikeWithLike, SeenWholeAtAnotherDensityOrSparselyTheWholePlanesAreCompared) {
    const Parameters p;
    const auto reference = relief(0.0, 0.02, -1.0, 1);
    const auto ref_blocks = blocks_of(reference, kBlock);
    // A quarter of the density, the footprint whole: not taken for a part.
    const auto coarse = blocks_of(relief(0.002, 0.04, -1.0, 3), kBlock);
    EXPECT_FALSE(seen_alike(ref_blocks, coarse).partial);
    const PatchResult r = compared_distance(ref_blocks, coarse, 0.0, p);
    const PatchResult direct =
        patch_distance(fit_plane(total(ref_blocks)), fit_plane(total(coarse)), 0.0, p);
    EXPECT_EQ(r.distance.distance, direct.distance.distance);
    EXPECT_FALSE(r.partial);
    EXPECT_EQ(r.reference.count, reference.size());
    EXPECT_NEAR(r.distance.distance, 0.002, r.distance.lod);
    // A sparse patch (6 m square, about one point a square metre, drawn at random in each
    // epoch): its blocks hold 16 points on average, and chance leaves none of them unseen.
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> at(0.0, 6.0);
    const auto sparse = [&]() {
        std::vector<Eigen::Vector3f> out;
        for (int k = 0; k < 36; ++k) out.emplace_back(float(at(rng)), float(at(rng)), 0.0f);
        return out;
    };
    const auto first = sparse();
    const double side = block_side(36.0, first.size());
    EXPECT_NEAR(side, 4.0, 1e-12);
    int partial = 0;
    for (int k = 0; k < 100; ++k)
        partial += seen_alike(blocks_of(first, side), blocks_of(sparse(), side)).partial;
    EXPECT_LE(partial, 5);
}

TEST(PatchLikeWithLike, ASliverSeenIsPartlySeen) {
    const Parameters p;
    const auto ref_blocks = blocks_of(relief(0.0, 0.02, -1.0, 1), kBlock);
    // Only u >= 0.8 seen: one column of blocks, and it borders the unseen ones.
    const auto sliver = blocks_of(relief(0.002, 0.02, 0.8, 5), kBlock);
    EXPECT_EQ(compared_distance(ref_blocks, sliver, 0.0, p).outcome, PatchOutcome::partly_seen);
    // The reference's own refusals come first: a rough reference stays `rough`.
    Parameters strict = p;
    strict.max_roughness = 0.001;
    EXPECT_EQ(compared_distance(ref_blocks, sliver, 0.0, strict).outcome, PatchOutcome::rough);
}

}  // namespace
}  // namespace tlsmon::patches
