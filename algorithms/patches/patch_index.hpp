#pragma once
// Which reference patch a point belongs to (docs/pbm3c2.md, "Correspondence"): the one whose
// footprint it projects into and whose plane it lies within the search depth of. When two
// qualify, a face and the face behind it: the one nearer along its normal. When their planes
// lie within kOneSurface of each other at the point, neighbours on one surface whose
// footprints share cells: the one whose footprint's centre is nearer in the plane. Not the
// nearer along the normal there, as that is decided by the point's noise: it would give the
// points the noise lifted to one patch and the rest to the other, a bias of a fraction of the
// noise in each plane, which cancels between epochs only while the surface stays within the
// noise of where it was (a face moved 1 mm along its normal: 90 % of the patches within the
// fits' LoD95 instead of 95 %). A selection by the place in the plane is unbiased: a range
// error moves a point along the plane as well, but every place there receives points with
// every error alike. A footprint is the set of square cells of the patch plane that its
// reference samples (the supervoxel's voxel centroids) project into — the patch's own
// outline, not a cylinder or a box around it.
//
// One index serves the reference's points and every epoch's alike: both are accumulated
// into the same patches by the same rule, so the two planes are fitted over one footprint.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "algorithms/patches/patch_plane.hpp"

namespace tlsmon::patches {

struct Footprint {
    double cell = 0.1;                          // m
    int u0 = 0, v0 = 0, width = 0, height = 0;  // cell range
    std::vector<std::uint8_t> occupied;         // width × height, row by v

    bool covers(double u, double v) const {
        const int i = int(std::floor(u / cell)) - u0, j = int(std::floor(v / cell)) - v0;
        return i >= 0 && j >= 0 && i < width && j < height &&
               occupied[std::size_t(j) * std::size_t(width) + std::size_t(i)];
    }
    std::size_t cells() const;
};

// The footprint of `samples` (points near the plane of `frame`) on cells of side `cell`.
Footprint footprint_of(const PatchFrame& frame, std::span<const Eigen::Vector3d> samples,
                       double cell);

struct Patch {
    PatchFrame frame;
    Footprint footprint;
};

// The centres of a patch's footprint cells, on its plane, in the reference frame.
std::vector<Eigen::Vector3d> cell_centres(const Patch& patch);

// m: two patches' planes this close at a point are one surface. Far above the noise and the
// offsets between neighbouring patches' planes (a tilt of 1e-3 over 0.5 m), far below the
// distance between a face and a face behind it.
inline constexpr double kOneSurface = 0.01;

class PatchIndex {
  public:
    PatchIndex(std::vector<Patch> patches, double search_depth);
    const std::vector<Patch>& patches() const { return patches_; }
    // The patch `p` belongs to, and its (u, v, w) there; −1 for none.
    std::int32_t find(const Eigen::Vector3d& p, Eigen::Vector3d& uvw) const;
    // visit(k, uvw) for every patch whose footprint and depth hold `p` (overlapping patches:
    // each of them).
    template <class Visit>
    void for_each(const Eigen::Vector3d& p, Visit&& visit) const {
        if (!bounds_.contains(p)) return;
        const auto it = cells_.find(key(p));
        if (it == cells_.end()) return;
        for (const auto k : it->second) {
            const Patch& patch = patches_[std::size_t(k)];
            const Eigen::Vector3d q = patch.frame.local(p);
            if (std::abs(q.z()) <= depth_ && patch.footprint.covers(q.x(), q.y())) visit(k, q);
        }
    }

  private:
    std::int64_t key(const Eigen::Vector3d& p) const;
    std::vector<Patch> patches_;
    std::vector<Eigen::Vector2d> centres_;  // per patch, its footprint cells' centroid (u, v)
    double depth_;
    double grid_ = 1.0;  // m, the side of the lookup cells
    Eigen::AlignedBox3d bounds_;
    std::unordered_map<std::int64_t, std::vector<std::int32_t>> cells_;
};

// A point on a patch: its (u, v, w) there and its index among the points.
struct PatchHit {
    Eigen::Vector3f uvw;
    std::uint32_t point;
};

// Every point's (u, v, w) on the patch it belongs to, after the affine map q = A·p + t into the
// reference frame (A = I, t = 0 for the reference itself): per patch, in the points' order
// (blocks of fixed size, joined in order: the same whatever the number of threads).
// With `every`, a point on overlapping patches is a hit of each of them. A point whose entry in
// `skip` (empty, or one per point) is non-zero is no hit.
std::vector<std::vector<PatchHit>> patch_hits(
    const PatchIndex& index, std::span<const Eigen::Vector3d> points,
    const Eigen::Matrix3d& A = Eigen::Matrix3d::Identity(),
    const Eigen::Vector3d& t = Eigen::Vector3d::Zero(), unsigned threads = 0, bool every = false,
    std::span<const std::uint8_t> skip = {});

// The same, the (u, v, w) alone.
std::vector<std::vector<Eigen::Vector3f>> patch_points(
    const PatchIndex& index, std::span<const Eigen::Vector3d> points,
    const Eigen::Matrix3d& A = Eigen::Matrix3d::Identity(),
    const Eigen::Vector3d& t = Eigen::Vector3d::Zero(), unsigned threads = 0,
    std::span<const std::uint8_t> skip = {});

}  // namespace tlsmon::patches
