#pragma once
// A supervoxel as a patch of plane, and its change between the reference and an epoch: the
// unit the registration on stable areas keeps in its datum or leaves out
// (docs/registration.md, "Registration on stable areas").
//
// Patch: the centroid c and the eigen-decomposition λ₀ ≤ λ₁ ≤ λ₂ of its voxels' scatter
// matrix; the normal n is the eigenvector of λ₀, the surface variation λ₀/(λ₀ + λ₁ + λ₂)
// (Pauly et al. 2002) says how planar it is, and s_r = √(λ₀/m) (m voxels) is the voxels'
// RMS distance from its plane.
//
// Change: the epoch's voxels paired with it, transformed, give the distances
// d_i = nᵀ(T·x_i − c); the change is their mean d̄ and its LoD at level α is
//   LoD = z_{1−α/2} · √(s_e²/m_e + s_r²/m + σ_T²)                     (as M3C2's, eq. 1 of
// Lague et al. 2013, with the registration's σ along n at c, σ_T, in place of its constant)
// where s_e is the epoch distances' standard deviation. A change beyond its LoD is
// significant.
#include <Eigen/Core>
#include <cstddef>
#include <span>

namespace tlsmon::registration {

struct SupervoxelPatch {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, towards the viewpoint
    double surface_variation = 1.0;                     // λ₀/(λ₀ + λ₁ + λ₂)
    double spread = 0.0;      // λ₁/λ₂: about 0 for voxels along a line, whose normal is free
    double sigma = 0.0;       // m, RMS distance of its voxels from the plane
    std::size_t samples = 0;  // voxels
};

// The patch of `points` (at least 3), its normal turned towards `viewpoint`.
SupervoxelPatch patch_of(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& viewpoint);

struct SupervoxelChange {
    double change = 0.0;       // m, d̄ along the patch normal
    double lod = 0.0;          // m, at the level asked
    double sigma_epoch = 0.0;  // m, s_e
    std::size_t samples = 0;   // m_e
    bool significant() const { return std::abs(change) > lod; }
};

// The change from the distances d_i (m) of the epoch's voxels, with the registration's σ along
// the normal at the centroid and the normal quantile z of the level. At least two distances.
SupervoxelChange change_of(const SupervoxelPatch& patch, std::span<const double> distances,
                           double registration_sigma, double z);

}  // namespace tlsmon::registration
