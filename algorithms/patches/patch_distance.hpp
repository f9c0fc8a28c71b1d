#pragma once
// The distance between a patch's reference plane and its plane in an epoch, and its level of
// detection (docs/pbm3c2.md; the thesis on rigid patches in TLS point clouds, §5.1).
//
// Both planes are fitted in the reference patch's frame (patch_plane.hpp). The distance is
// taken along the patch normal at the reference points' centroid projected onto the patch
// plane, (ū₁, v̄₁) — between the two planes, not as a mean of raw point distances, so that a
// slope or a different sampling of the footprint in the epoch does not bias it:
//   d = h₂(ū₁, v̄₁) − h₁(ū₁, v̄₁)
// and by error propagation of the two independent fits and the registration's σ along the
// normal at the patch, σ_T:
//   σ_d² = σ₁²/m₁ + σ_h₂(ū₁, v̄₁)² + σ_T²,   LoD95 = 1.96·σ_d,
// significant when |d| > LoD95. Unlike M3C2's LoD (Lague 2013, eq. 1), σ_T adds in
// quadrature: the registration's error and the fits' are independent.
#include <cstddef>
#include <limits>

#include "algorithms/patches/parameters.hpp"
#include "algorithms/patches/patch_plane.hpp"

namespace tlsmon::patches {

struct PatchDistance {
    double distance = std::numeric_limits<double>::quiet_NaN();  // m, along the normal
    double sigma = std::numeric_limits<double>::quiet_NaN();     // m, σ_d
    double lod = std::numeric_limits<double>::quiet_NaN();       // m, LoD95
    // m, √(σ₁²/m₁ + σ_h₂²): the fits' part of σ_d (what averages out over a zone)
    double sampling_sigma = std::numeric_limits<double>::quiet_NaN();
    bool significant = false;
};

// Why a patch has no distance, or `measured`.
enum class PatchOutcome {
    measured,
    rough,
    few_reference_points,
    few_epoch_points,
    partly_seen  // the part of the footprint both epochs saw alike is too small or not a plane
};

struct PatchResult {
    PatchOutcome outcome = PatchOutcome::few_reference_points;
    PatchDistance distance;
    // The two fits the distance rests on, or was refused on; the distance is taken over
    // `reference`'s centroid, (ū₁, v̄₁, h₁) in the patch frame.
    PlaneFit reference, epoch;
    bool partial = false;  // the fits are over the part both epochs saw alike (like_with_like)
};

// tan of the largest angle between the reference points' fitted plane and the patch's own
// plane (its supervoxel's): beyond it the points are not the surface the supervoxel described
// (one spanning a corner, whose points on one of the two faces were left out as edge points),
// and the patch normal is not the direction in which that surface moves. A plane's own patches
// agree within a fraction of a degree.
inline constexpr double kMaxPatchTilt = 0.176;  // 10°

// NaN distance (outcome `rough`) unless both fits are valid with at least min_points and the
// reference's σ₁ is at most max_roughness and its plane within kMaxPatchTilt of the patch's.
PatchResult patch_distance(const PlaneFit& reference, const PlaneFit& epoch,
                           double registration_sigma, const Parameters& parameters);

}  // namespace tlsmon::patches
