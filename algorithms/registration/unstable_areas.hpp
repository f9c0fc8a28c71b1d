#pragma once
// Unstable supervoxels grouped into areas: neighbours (centroids within a reach) joined, each
// area summarised by where it is, how it faces and how much it changed — the finding behind an
// `unstable_area` event and the box of a zone that would measure it (docs/registration.md,
// "Unstable areas").
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlsmon::registration {

// One supervoxel as the grouping sees it (reference frame; change and LoD in metres along its
// normal, NaN: none).
struct AreaPatch {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    float change = 0, lod = 0;
};

struct UnstableArea {
    std::vector<std::uint32_t> supervoxels;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // mean of their centroids
    Eigen::Vector3d lower = Eigen::Vector3d::Zero();   // bounding box of the centroids
    Eigen::Vector3d upper = Eigen::Vector3d::Zero();
    double extent = 0;  // m, farthest centroid from the centre
    // Mean normal (unit, signs aligned to the first), and the largest angle of a member's
    // normal from it: a slope is one face, a parked vehicle is not.
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    double normal_spread_rad = 0;
    double min_change = 0, max_change = 0;  // m, this epoch
    double max_lod = 0;                     // m
};

// An area holds at least this many supervoxels (a few square metres): one patch that stays
// unstable alone is more often an edge (the top of a block face, mixed returns) than a
// movement of the ground.
constexpr std::size_t kMinAreaSupervoxels = 3;

// The supervoxels whose state byte is `unstable` in `now` and in the `count` − 1 masks before
// it (`before`: newest first); with `first_time`, only those that were not so in the mask before
// those as well (an area is reported once, when it gets there). None when the history is
// shorter or from another segmentation (a mask of another size).
std::vector<std::uint32_t> unstable_run(const std::vector<std::uint8_t>& now,
                                        const std::vector<std::vector<std::uint8_t>>& before,
                                        int count, std::uint8_t unstable, bool first_time);

// The areas formed by `members` (indices into `patches`): single linkage with centroids within
// `reach` (union–find), areas of fewer than kMinAreaSupervoxels left out, in the order of their
// smallest member.
std::vector<UnstableArea> unstable_areas(const std::vector<AreaPatch>& patches,
                                         const std::vector<std::uint32_t>& members, double reach);

}  // namespace tlsmon::registration
