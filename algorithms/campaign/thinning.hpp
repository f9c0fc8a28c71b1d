#pragma once
// Thinning a dense campaign cloud on a voxel grid before classifying it (verticality,
// segmentation): a personal scanner puts tens of points per square centimetre next to the
// walker and a few per square decimetre far away, and the cost of a fixed-radius
// neighbourhood grows with the density. Each voxel keeps the first of its points in the
// cloud's order (a scanner's order is its time). Every point keeps its voxel's index, so
// what is found on the kept points (a class, a segment) goes back to all of them.
//
// Not for measuring: one point per voxel weights every voxel a noisy surface touches alike,
// those its noise's tail reaches as much as those it runs through, so the kept points' mean
// offset from the surface depends on where the surface lies in the voxel grid (±1 mm for
// 20 mm noise and 0.03 m voxels, tests/algorithms/test_campaign_thinning.cpp). A
// registration takes a subsample that does not look at the positions.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace tlsmon::campaign {

struct VoxelThinning {
    static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    double voxel = 0;               // m, the cube's edge; 0: every point is its own voxel
    std::vector<std::uint32_t> of;  // per point, its voxel; kNone: not finite or not taken
    std::vector<std::size_t> kept;  // per voxel, the point that stands for it
    std::size_t voxels() const { return kept.size(); }
};

// The voxels of `points` whose `take` flag is set (empty: every point), on the grid of cubes
// of `voxel` (m) from the origin. The result does not depend on `threads` (0: every core).
VoxelThinning thin_by_voxel(std::span<const Eigen::Vector3d> points, double voxel,
                            std::span<const std::uint8_t> take = {}, unsigned threads = 0);

// The kept points themselves.
std::vector<Eigen::Vector3d> kept_points(std::span<const Eigen::Vector3d> points,
                                         const VoxelThinning& thinning);

}  // namespace tlsmon::campaign
