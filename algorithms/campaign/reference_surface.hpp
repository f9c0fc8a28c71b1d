#pragma once
// The TLS reference a campaign cloud is compared with: its points on a grid, each with its
// local plane (local_plane.hpp), so that a campaign point finds its nearest reference point
// and the surface there.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/campaign/local_plane.hpp"
#include "algorithms/campaign/point_grid.hpp"
#include "algorithms/campaign/thinning.hpp"

namespace tlsmon::campaign {

struct ReferenceSurfaceParameters {
    double plane_radius = 0.10;  // m, the local planes' neighbourhood (the study's radius)
    int min_neighbours = 6;
    double max_distance = 0.20;  // m, the farthest a nearest neighbour is looked for
    // The largest surface variation of a local plane that models the surface (local_plane.hpp;
    // 0.01: σ ≈ 7 mm about the plane at the 0.10 m radius). Beyond it — an edge, a corner —
    // a pair is left out of the point-to-plane fit and C2C falls back to the nearest point: a
    // plane fitted across an edge stands off both faces.
    double max_variation = 0.01;
    // m, a local plane is fitted at the first point of each voxel this size (thinning.hpp), of
    // its neighbours among all the points, and serves the voxel's points: neighbouring planes
    // at half the radius share most of their neighbourhood, so a dense reference need not fit
    // one per point. 0: a plane at every point.
    double plane_spacing = 0.05;
};

class ReferenceSurface {
  public:
    // `points` must outlive the surface.
    ReferenceSurface(std::span<const Eigen::Vector3d> points,
                     const ReferenceSurfaceParameters& parameters, unsigned threads = 0);

    // The nearest reference point within max_distance of x, −1 when there is none.
    std::int64_t nearest(const Eigen::Vector3d& x) const;

    const Eigen::Vector3d& point(std::int64_t i) const { return points_[std::size_t(i)]; }
    // The local plane that serves point i (plane_spacing).
    const LocalPlane& plane(std::int64_t i) const { return planes_[voxels_.of[std::size_t(i)]]; }
    // Whether point i's local plane models the surface there (max_variation).
    bool planar(std::int64_t i) const {
        const LocalPlane& p = plane(i);
        return p.defined() && p.variation <= parameters_.max_variation;
    }
    std::size_t planes() const { return planes_.size(); }
    std::size_t size() const { return points_.size(); }
    const ReferenceSurfaceParameters& parameters() const { return parameters_; }

  private:
    std::span<const Eigen::Vector3d> points_;
    ReferenceSurfaceParameters parameters_;
    PointGrid grid_;
    VoxelThinning voxels_;  // a non-finite point's plane is the undefined last one
    std::vector<LocalPlane> planes_;
};

void validate(const ReferenceSurfaceParameters& parameters);

}  // namespace tlsmon::campaign
