#include "algorithms/campaign/reference_surface.hpp"

#include <limits>

#include "core/error.hpp"

namespace tlsmon::campaign {

void validate(const ReferenceSurfaceParameters& p) {
    if (!(p.plane_radius > 0 && p.plane_radius <= 100))
        throw Error("campaign: plane_radius must lie in (0, 100] m");
    if (p.min_neighbours < 3) throw Error("campaign: min_neighbours must be at least 3");
    if (!(p.max_distance > 0 && p.max_distance <= 100))
        throw Error("campaign: max_distance must lie in (0, 100] m");
    if (!(p.max_variation > 0 && p.max_variation <= 1.0 / 3))
        throw Error("campaign: max_variation must lie in (0, 1/3]");
    if (!(p.plane_spacing >= 0 && p.plane_spacing <= p.plane_radius))
        throw Error("campaign: plane_spacing must lie in [0, plane_radius]");
}

namespace {
const ReferenceSurfaceParameters& checked(const ReferenceSurfaceParameters& p) {
    validate(p);
    return p;
}
}  // namespace

ReferenceSurface::ReferenceSurface(std::span<const Eigen::Vector3d> points,
                                   const ReferenceSurfaceParameters& parameters, unsigned threads)
    : points_(points),
      parameters_(checked(parameters)),
      grid_(points, std::max(parameters.plane_radius, parameters.max_distance / 2)),
      voxels_(thin_by_voxel(points, parameters.plane_spacing, {}, threads)),
      planes_(local_planes(points, parameters.plane_radius, parameters.min_neighbours, threads,
                           voxels_.kept)) {
    // Non-finite points (never a nearest point) share one undefined plane.
    for (auto& v : voxels_.of)
        if (v == VoxelThinning::kNone) v = std::uint32_t(planes_.size());
    planes_.emplace_back();
}

std::int64_t ReferenceSurface::nearest(const Eigen::Vector3d& x) const {
    // Growing spheres: most points have a neighbour within a small fraction of max_distance,
    // and a small sphere visits few points. A hit at radius r is the nearest overall.
    for (double radius = parameters_.max_distance / 8;; radius *= 2) {
        radius = std::min(radius, parameters_.max_distance);
        std::int64_t best = -1;
        double best_d2 = std::numeric_limits<double>::infinity();
        grid_.within(x, radius, [&](std::uint32_t k, double d2) {
            if (d2 < best_d2) {
                best_d2 = d2;
                best = k;
            }
        });
        if (best >= 0 || radius >= parameters_.max_distance) return best;
    }
}

}  // namespace tlsmon::campaign
