// Where a patch's distance is placed (PbM3c2Reference::measured_at) and what the stored arrays
// keep of it (pbm3c2_patch_arrays): an epoch that saw the patch whole is placed over the whole
// reference plane's centroid, with a stored shift of 0; one that saw only part of it over that
// part's centroid, and the stored shift gives that place back (docs/pbm3c2.md, "Like with
// like").
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <string>
#include <vector>

#include "pipeline/pbm3c2_stage.hpp"

namespace tlsmon {
namespace {

// A patch 1 m square in its frame (u, v in [0, 1)), tilted 1 cm per metre along u, seen every
// 2 cm where u >= u_min, with 0.5 mm of noise, raised by w0.
std::vector<Eigen::Vector3f> tilted(double w0, double u_min, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.0005);
    std::vector<Eigen::Vector3f> out;
    for (double u = 0.01; u < 1.0; u += 0.02)
        for (double v = 0.01; v < 1.0; v += 0.02)
            if (u >= u_min) out.emplace_back(float(u), float(v), float(w0 + 0.01 * u + noise(rng)));
    return out;
}

std::vector<patches::BlockMoments> blocks_of(const std::vector<Eigen::Vector3f>& uvw) {
    return patches::block_moments(uvw, std::vector<std::uint8_t>(uvw.size(), 1), patches::kBlock);
}

struct OnePatch {
    PbM3c2Reference reference;
    OnePatch() {
        reference.patches.resize(1);
        reference.patches[0].frame =
            patches::PatchFrame::about({10.0, 20.0, 5.0}, Eigen::Vector3d(0.6, -0.8, 0.0));
        reference.blocks = {blocks_of(tilted(0.0, -1.0, 1))};
        reference.moments = {patches::total(reference.blocks[0])};
        reference.block_side = {patches::kBlock};
        reference.supervoxel = {0};
    }
    PbM3c2Epoch measure(double u_min) const {
        PbM3c2Epoch e;
        const auto epoch = blocks_of(tilted(0.002, u_min, 2));
        e.moments = {patches::total(epoch)};
        e.registration_sigma = {0.0};
        e.results = {patches::compared_distance(reference.blocks[0], epoch, 0.0, {})};
        return e;
    }
};

// The arrays' values at the one patch, by name.
std::map<std::string, float> stored(const PbM3c2Reference& reference, const PbM3c2Epoch& epoch) {
    std::map<std::string, float> out;
    for (const auto& a : pbm3c2_patch_arrays(reference, epoch)) out[a.quantity] = a.values.at(0);
    return out;
}

TEST(PbM3c2Place, SeenWholeTheDistanceIsPlacedOverTheWholePlane) {
    const OnePatch p;
    const PbM3c2Epoch e = p.measure(-1.0);
    const auto& r = e.results[0];
    ASSERT_EQ(r.outcome, patches::PatchOutcome::measured);
    EXPECT_FALSE(r.partial);
    EXPECT_EQ(p.reference.measured_at(0, &r), p.reference.measured_at(0));
    const Eigen::Vector3d centre = p.reference.measured_in_frame(0);
    EXPECT_NEAR(centre.x(), 0.5, 1e-7);
    EXPECT_NEAR(centre.y(), 0.5, 1e-7);
    EXPECT_NEAR(centre.z(), 0.005, 1e-4);  // the tilt's height at u = 0.5
    // No shift anywhere: none stored.
    const auto a = stored(p.reference, e);
    EXPECT_EQ(a.size(), 4u);
    EXPECT_EQ(a.count("pbm3c2_shift_u_m"), 0u);
    EXPECT_EQ(a.at("pbm3c2_n1"), 2500.0f);
    EXPECT_EQ(a.at("pbm3c2_n2"), 2500.0f);
}

TEST(PbM3c2Place, SeenInPartTheDistanceIsPlacedOverThePartSeen) {
    const OnePatch p;
    // Seen on u >= 0.4: the blocks from u = 0.6 are compared (those at 0.4 border the unseen).
    const PbM3c2Epoch e = p.measure(0.4);
    const auto& r = e.results[0];
    ASSERT_EQ(r.outcome, patches::PatchOutcome::measured);
    EXPECT_TRUE(r.partial);
    EXPECT_NEAR(r.distance.distance, 0.002, r.distance.lod);
    const Eigen::Vector3d part = p.reference.measured_in_frame(0, &r);
    EXPECT_NEAR(part.x(), 0.8, 1e-7);
    EXPECT_NEAR(part.y(), 0.5, 1e-7);
    EXPECT_NEAR(part.z(), 0.008, 1e-4);  // on the reference plane, over u = 0.8
    // In the site's frame (the points are float32): 0.3 m along u and 3 mm along the normal from
    // the whole plane's place.
    const Eigen::Vector3d moved = p.reference.measured_at(0, &r) - p.reference.measured_at(0);
    const auto& frame = p.reference.patches[0].frame;
    EXPECT_NEAR(moved.dot(frame.u), 0.3, 1e-7);
    EXPECT_NEAR(moved.dot(frame.v), 0.0, 1e-7);
    EXPECT_NEAR(moved.dot(frame.normal), 0.003, 1e-4);
    // The stored shift, float32, gives the place back (as the LAS export reads it).
    const auto a = stored(p.reference, e);
    const Eigen::Vector3d shift(a.at("pbm3c2_shift_u_m"), a.at("pbm3c2_shift_v_m"),
                                a.at("pbm3c2_shift_w_m"));
    const Eigen::Vector3d back =
        p.reference.from_frame(0, p.reference.measured_in_frame(0) + shift);
    EXPECT_LT((back - p.reference.measured_at(0, &r)).norm(), 1e-7);
    EXPECT_EQ(a.at("pbm3c2_n1"), 1000.0f);
    EXPECT_EQ(a.at("pbm3c2_n2"), 1000.0f);
}

}  // namespace
}  // namespace tlsmon
