#pragma once
// The covariance of a registration on stable areas with each supervoxel of its datum as one
// observation of its change (docs/registration.md, "Registration on stable areas", step 5):
//   d_k = a_kᵀ·δ + u_c + e_k,   a_k = ((c_k − t) × n_k, n_k) as the adjustment's rows,
// e_k its own error, of variance σ_k² = s_e²/m_e + s_r²/m (the reference plane's error s_r/√m
// is common to all its voxels, which the voxel-level adjustment takes as independent), and u_c
// an error common to the supervoxels of a cell (a face's systematic change: the beam's
// footprint on its texture, its incidence), of variance τ² pooled over every cell. With the
// adjustment's weights W_k (its voxels' weight times their number):
//   C = N⁻¹·(Σ_k W_k²·σ_k²·a_k·a_kᵀ + τ²·Σ_c b_c·b_cᵀ)·N⁻¹,
//   N = Σ_k W_k·a_k·a_kᵀ,   b_c = Σ_{k∈c} W_k·a_k.
// τ² from the cells' weighted mean residual changes r̄_c, each of variance v_c = Σ W_k²·σ_k² /
// (Σ W_k)² without a common error: the Paule & Mandel (1982) estimator, the τ² at which
//   Σ_c r̄_c²/(v_c + τ²) = C − 6
// (C cells, six parameters fitted; the residuals are the adjustment's, not refitted with these
// weights), kept only when Q = Σ_c r̄_c²/v_c is significant against χ²(C − 6) at 5 % (as the
// ICP's cells, point_to_plane.hpp). Each cell counts by 1/(v_c + τ²): not alike, where one far
// supervoxel alone in its cell would set τ for all, nor by its precision alone (DerSimonian &
// Laird 1986), where the near ground's many precise cells dilute an error common to a few
// (a moved part that stayed within its LoD). Veroniki et al. (2016) recommend it over both.
// Pooled over all cells, τ² reaches a direction that only a few cells hold, which a sandwich of
// those few cells' own scores may miss.
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <span>

#include "algorithms/registration/point_to_plane.hpp"

namespace tlsmon::registration {

struct SupervoxelObservation {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // c_k, reference frame
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   // n_k, unit
    double weight = 0.0;    // W_k: the adjustment's weight of its voxels, summed
    double change = 0.0;    // m, its change under the adjustment's transformation (a residual)
    double variance = 0.0;  // m², σ_k² of the change without the registration's part
};

// The cells the common error u_c is shared by: cubes of `size` from the corner `origin`. The
// corner must lie off the scene's round coordinates: a face or level ground on a cell boundary
// is split by the sign of its supervoxels' centroid errors, which are in their changes, and the
// two halves then look like two cells with opposite common errors.
struct CellGrid {
    double size = 5.0;  // m
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};

struct SupervoxelCovariance {
    Covariance6 covariance = Covariance6::Zero();  // of (θ, t)
    double cell_sigma = 0.0;                       // τ, m; 0 unless significant
    double q = 0.0;                                // Σ_c r̄_c²/v_c
    std::size_t cells = 0;
    bool significant = false;  // Q beyond χ²(C − 6) at 5 %
};

// The covariance about the translation t. Nothing with 6 cells or fewer, or a singular N.
// Observations without a positive weight and variance are left out.
std::optional<SupervoxelCovariance> supervoxel_covariance(
    std::span<const SupervoxelObservation> observations, const Eigen::Vector3d& t,
    const CellGrid& grid);

}  // namespace tlsmon::registration
