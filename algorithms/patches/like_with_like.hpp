#pragma once
// A patch's two planes fitted over the part of its footprint that both epochs saw alike
// (docs/pbm3c2.md, "Like with like").
//
// On a plane, the epoch's fit over any part of the footprint gives the plane, and the distance
// taken at the reference's centroid is unbiased (patch_distance.hpp), its σ growing with the
// way from the part seen. On relief it is not: what is left of the relief in a plane fitted
// over part of the footprint differs from what is left in one over all of it, by up to the
// relief's size, and that difference repeats in every epoch, so no fit's σ holds it. Where an
// epoch sees only part of what the reference saw (an occluder in front, the scan's window
// moved, a shadow cast anew), both sides are therefore fitted over the blocks (squares of
// kBlock on the patch plane) that both saw alike: the relief is then common to both planes
// and cancels in the distance, as it does when the whole footprint is seen.
//
// A block of the reference is not seen alike when the epoch holds less than half the points
// there that its density elsewhere on the patch gives, e = ρ·n₁ (ρ the upper quartile of the
// ratios n₂/n₁ of the blocks it has points in: the epoch's density relative to the
// reference's where it saw the patch, so that a scan at another resolution is not taken for
// one that saw part), and so few that chance does not explain it: n₂ < e − 3√e (a count's
// Poisson σ). When the blocks not seen alike hold at most kUnseenShare of the reference's
// points, and the epoch has at most that share outside the reference's blocks, the whole
// planes are compared. Otherwise the blocks seen alike are, less those next to a block not
// seen (the edge of what the epoch saw may run through them).
#include <cstdint>
#include <vector>

#include "algorithms/patches/parameters.hpp"
#include "algorithms/patches/patch_distance.hpp"
#include "algorithms/patches/patch_plane.hpp"

namespace tlsmon::patches {

inline constexpr double kBlock = 0.2;         // m: two footprint cells, at least
inline constexpr double kBlockPoints = 16;    // reference points a block holds, at least
inline constexpr double kUnseenShare = 0.05;  // of a side's points

// The side of a patch's blocks: kBlock, or larger where the reference is sparse, so that a
// block holds kBlockPoints of its `points` over `area` (m²) on average.
double block_side(double area, std::size_t points);

// The moments of a patch's points in block (i, j): u in [i·side, (i + 1)·side), v alike.
struct BlockMoments {
    std::int32_t i = 0, j = 0;
    PlaneMoments moments;
};

// The points' moments per block of `side`, in (j, i) order; only those with keep[k] != 0.
std::vector<BlockMoments> block_moments(const std::vector<Eigen::Vector3f>& uvw,
                                        const std::vector<std::uint8_t>& keep, double side);

// The sum over the blocks.
PlaneMoments total(const std::vector<BlockMoments>& blocks);

// The moments of the two sides over the blocks seen alike; `partial` false when the whole
// sides are compared (their totals). The whole sides' totals beside them.
struct SeenAlike {
    PlaneMoments reference, epoch;
    bool partial = false;
    PlaneMoments reference_total, epoch_total;
};
SeenAlike seen_alike(const std::vector<BlockMoments>& reference,
                     const std::vector<BlockMoments>& epoch);

// patch_distance between the sides seen alike. The reference's checks (min_points,
// max_roughness, its tilt) are made on its whole plane; when the part seen alike is too small
// or not a plane on its own, the outcome is `partly_seen`.
PatchResult compared_distance(const std::vector<BlockMoments>& reference,
                              const std::vector<BlockMoments>& epoch, double registration_sigma,
                              const Parameters& parameters);

}  // namespace tlsmon::patches
