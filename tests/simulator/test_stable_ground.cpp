// The simulator's stable ground (simulator/stable_ground.hpp): for every preset no box
// touches the pier or the deck, and the foundation's and abutments' tops are inside one.
#include <gtest/gtest.h>

#include "simulator/stable_ground.hpp"

namespace tlsmon::sim {
namespace {

bool overlaps(const StableBox& b, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return (b.min.array() < hi.array()).all() && (b.max.array() > lo.array()).all();
}

TEST(StableGround, NeverThePierAlwaysTheBlocks) {
    for (const auto& name : preset_names()) {
        const Site s = preset(name);
        const auto boxes = stable_ground(s);
        ASSERT_FALSE(boxes.empty()) << name;
        const Eigen::Vector3d pier_lo(s.pier.x0, s.pier.y0, 0.0);
        const Eigen::Vector3d pier_hi(s.pier.x1, s.pier.y1, s.pier.height);
        const double cy = 0.5 * (s.pier.y0 + s.pier.y1);
        const Eigen::Vector3d deck_lo(s.pier.x0 - s.deck.overhang, cy - s.deck.half_length,
                                      s.pier.height);
        const Eigen::Vector3d deck_hi(s.pier.x1 + s.deck.overhang, cy + s.deck.half_length,
                                      s.pier.height + s.deck.thickness);
        for (const auto& b : boxes) {
            EXPECT_FALSE(overlaps(b, pier_lo, pier_hi)) << name << " " << b.name;
            EXPECT_FALSE(overlaps(b, deck_lo, deck_hi)) << name << " " << b.name;
        }
        for (const auto& block : s.terrain.blocks) {
            // A point on the block's top, off the pier's footprint by 0.5 m.
            const Eigen::Vector3d p(block.lo.x() + 0.5, block.lo.y() + 0.5, block.hi.z());
            bool inside = false;
            for (const auto& b : boxes) {
                inside = inside ||
                         ((p.array() >= b.min.array()).all() && (p.array() <= b.max.array()).all());
            }
            EXPECT_TRUE(inside) << name << " " << block.name;
        }
    }
}

}  // namespace
}  // namespace tlsmon::sim
