// Matching in an angular window with descriptors of known distances: the nearest
// descriptor inside the window wins, nothing outside it can, the ±π wrap is one window, and
// the ratio test and mutual check drop exactly the ambiguous pairs.
#include <gtest/gtest.h>

#include <numbers>

#include "algorithms/keypoints/keypoint_matching.hpp"
#include "core/error.hpp"

namespace {

using namespace tlsmon::keypoints;
constexpr double deg = std::numbers::pi / 180.0;

// 8-byte binary descriptors whose first byte has `bits` low bits set: the Hamming distance
// of two is the difference of their bit counts.
Descriptors binary(const std::vector<int>& bits) {
    Descriptors d;
    d.binary = true;
    d.length = 8;
    for (int b : bits) {
        std::vector<std::uint8_t> row(8, 0);
        row[0] = static_cast<std::uint8_t>((1u << b) - 1u);
        d.bits.insert(d.bits.end(), row.begin(), row.end());
    }
    return d;
}

TEST(KeypointMatching, DescriptorDistances) {
    const Descriptors a = binary({3, 0});
    EXPECT_EQ(descriptor_distance(a, 0, a, 1), 3.0);
    Descriptors f;
    f.binary = false;
    f.length = 2;
    f.values = {0, 0, 3, 4};
    EXPECT_DOUBLE_EQ(descriptor_distance(f, 0, f, 1), 5.0);
    EXPECT_THROW(descriptor_distance(a, 0, f, 0), tlsmon::Error);
}

TEST(KeypointMatching, NearestDescriptorInsideTheWindowWins) {
    // Reference keypoint 0 at (10°, 5°); epoch candidates: a close descriptor just outside the
    // 0.05° window, a farther one inside, and a worse one inside.
    const std::vector<AngularPosition> ref = {{10 * deg, 5 * deg}};
    const std::vector<AngularPosition> epoch = {
        {10.06 * deg, 5 * deg}, {10.03 * deg, 5.02 * deg}, {9.98 * deg, 4.99 * deg}};
    const auto pairs = match_keypoints(ref, binary({4}), epoch, binary({4, 5, 7}), {});
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0].reference, 0u);
    EXPECT_EQ(pairs[0].epoch, 1u);
    EXPECT_EQ(pairs[0].distance, 1.0);
    // No candidate in the window: no pair.
    EXPECT_TRUE(
        match_keypoints(ref, binary({4}), {{10.2 * deg, 5 * deg}}, binary({4}), {}).empty());
}

TEST(KeypointMatching, WindowSpansTheAzimuthWrap) {
    const double pi = std::numbers::pi;
    const std::vector<AngularPosition> ref = {{pi - 0.01 * deg, 0}};
    const std::vector<AngularPosition> epoch = {{-pi + 0.02 * deg, 0}, {pi - 0.2 * deg, 0}};
    const auto pairs = match_keypoints(ref, binary({2}), epoch, binary({3, 2}), {});
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0].epoch, 0u);  // 0.03° away across the wrap; the other is 0.19° away
}

TEST(KeypointMatching, RatioTestAndMutualCheck) {
    const std::vector<AngularPosition> ref = {{0, 0}, {0.01 * deg, 0}};
    const std::vector<AngularPosition> epoch = {{0.005 * deg, 0}, {0.0, 0.01 * deg}};
    // Reference 0 (bits 4) sees epoch 0 (bits 5, distance 1) and epoch 1 (bits 6, distance 2);
    // reference 1 (bits 5) sees epoch 0 at distance 0.
    const Descriptors rd = binary({4, 5});
    const Descriptors ed = binary({5, 6});
    MatchingParameters p;
    auto pairs = match_keypoints(ref, rd, epoch, ed, p);
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0].epoch, 0u);
    EXPECT_EQ(pairs[1].epoch, 0u);
    // Ratio 0.4: reference 0's best (1) is not below 0.4 × its second (2) → dropped;
    // reference 1's best (0) is below 0.4 × 1 → kept.
    p.ratio = 0.4;
    pairs = match_keypoints(ref, rd, epoch, ed, p);
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0].reference, 1u);
    // Mutual: epoch 0's nearest reference keypoint is reference 1 (distance 0), so reference 0
    // → epoch 0 is dropped.
    p.ratio = 0.0;
    p.mutual = true;
    pairs = match_keypoints(ref, rd, epoch, ed, p);
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0].reference, 1u);
    EXPECT_EQ(pairs[0].epoch, 0u);
}

TEST(KeypointMatching, WindowFollowsTheRange) {
    // A keypoint at 3 m and one at 150 m, each moved 10 mm across the beam: 0.19° and
    // 0.0038°. With the defaults (0.05°, 0.02 m) both are matched; the fixed angle alone loses
    // the near one, whose motion is wider than it.
    const double near = 3.0, far = 150.0, w = 0.010;
    const std::vector<AngularPosition> ref = {{10 * deg, 0}, {40 * deg, 0}};
    const std::vector<AngularPosition> epoch = {{10 * deg + w / near, 0}, {40 * deg + w / far, 0}};
    const std::vector<double> ranges = {near, far};
    const MatchingParameters defaults;
    EXPECT_NEAR(window_radius_at(defaults, near), 0.02 / near, 1e-15);
    EXPECT_DOUBLE_EQ(window_radius_at(defaults, far), 0.05 * deg);
    EXPECT_DOUBLE_EQ(window_radius_at(defaults, 0.0), 0.05 * deg);  // no range: the angle
    const auto pairs = match_keypoints(ref, binary({3, 6}), epoch, binary({3, 6}), {}, ranges);
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0].epoch, 0u);
    EXPECT_EQ(pairs[1].epoch, 1u);
    MatchingParameters angle_only;
    angle_only.window_m = 0;
    const auto fixed =
        match_keypoints(ref, binary({3, 6}), epoch, binary({3, 6}), angle_only, ranges);
    ASSERT_EQ(fixed.size(), 1u);
    EXPECT_EQ(fixed[0].reference, 1u);
    // A motion beyond window_m at 3 m is not matched (the window is not unbounded).
    const std::vector<AngularPosition> too_far = {{10 * deg + 0.025 / near, 0}, epoch[1]};
    EXPECT_EQ(match_keypoints(ref, binary({3, 6}), too_far, binary({3, 6}), {}, ranges).size(), 1u);
}

TEST(KeypointMatching, BadParameters) {
    const std::vector<AngularPosition> one = {{0, 0}};
    MatchingParameters p;
    p.window_radius = 0;
    EXPECT_THROW(match_keypoints(one, binary({1}), one, binary({1}), p), tlsmon::Error);
    p = {};
    p.ratio = 1.5;
    EXPECT_THROW(match_keypoints(one, binary({1}), one, binary({1}), p), tlsmon::Error);
    EXPECT_THROW(match_keypoints(one, binary({1, 2}), one, binary({1}), {}), tlsmon::Error);
    p = {};
    p.window_m = -0.01;
    EXPECT_THROW(match_keypoints(one, binary({1}), one, binary({1}), p), tlsmon::Error);
    const std::vector<double> two_ranges = {3.0, 4.0};
    EXPECT_THROW(match_keypoints(one, binary({1}), one, binary({1}), {}, two_ranges),
                 tlsmon::Error);
}

}  // namespace
