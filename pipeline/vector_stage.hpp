#pragma once
// Stage "vectors": 3-D displacement vectors by local registration of quasi-rigid areas
// (docs/vectors.md; the thesis on rigid patches in TLS point clouds, §5.3) of each epoch
// against the reference epoch, on the reference's patches inside the zones, aggregated per
// zone into the time series.
//
// Reference product (the reference cache, stage "vectors"): the patches — the supervoxels of
// the registration on stable areas, from the same cache entry, segmented once
// (pipeline/zone_patches.hpp) — each an area: the square `window` about the patch's centroid
// in its plane, with the reference's samples (u, v, w, intensity) in it.
//
// Each epoch: its points mapped into the reference frame (the registration and the range
// scales, as for M3C2: epoch_to_reference), gathered per area in the window widened by the
// search radius and the kernel's reach, each area registered on its own
// (algorithms/vectors/area_registration.hpp); the vector in the project frame with its
// covariance, Σ = R·Σ_area·Rᵀ + Σ_T, Σ_T the registration's at the area (0 without a
// registration: the epoch then carries that quality and raises no deformation alarm).
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/stable_area_registration.hpp"
#include "pipeline/stage.hpp"
#include "pipeline/vector_config.hpp"
#include "pipeline/vector_reference.hpp"

namespace tlsmon {

// The zone quantities the stage writes, per zone and epoch (the alarm rules name them).
inline constexpr std::array<const char*, 7> kVectorQuantities = {"vector_count",
                                                                 "vector_dx_m",
                                                                 "vector_dy_m",
                                                                 "vector_dz_m",
                                                                 "vector_along_normal_m",
                                                                 "vector_along_surface_h_m",
                                                                 "vector_along_surface_v_m"};

// The canonical text of every parameter the reference product depends on (its cache key).
std::string vector_reference_parameters(const VectorConfig& config);

VectorReference prepare_vector_reference(const VectorConfig& config,
                                         const ReferenceSupervoxels& supervoxels,
                                         const std::vector<Scan>& scans);

// One area's vector in the project frame.
struct AreaDisplacement {
    vectors::AreaVector fit;  // in the area's frame (u, v, normal)
    Eigen::Vector3d displacement = Eigen::Vector3d::Constant(std::nan(""));  // m
    Eigen::Matrix3d fit_covariance = Eigen::Matrix3d::Zero();           // m², R·Σ_area·Rᵀ
    Eigen::Matrix3d registration_covariance = Eigen::Matrix3d::Zero();  // m², Σ_T at the area
    // m²: the between-area variance τ² of its zone (the largest of its zones'), in the
    // zone's wall directions (algorithms/vectors/between_area_variance.hpp).
    Eigen::Matrix3d between_covariance = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d covariance() const {
        return fit_covariance + between_covariance + registration_covariance;
    }
};

struct VectorEpoch {
    std::vector<AreaDisplacement> areas;
    // The registration's covariance at each zone's areas' centroid (zero without one).
    std::vector<Eigen::Matrix3d> zone_registration_covariance;
    // Each zone's between-area variance: τ² along its normal, h and v (m, as σ), and as a
    // covariance in the project frame.
    std::vector<Eigen::Vector3d> zone_between_sigma;
    std::vector<Eigen::Matrix3d> zone_between_covariance;
};

VectorEpoch measure_vectors(const VectorConfig& config, const VectorReference& reference,
                            const std::vector<Scan>& scans, const StageOutputs& outputs);

// The zone's frame the along-normal and along-surface figures are taken in: the zone's design
// normal (else its areas' mean normal) towards the scanner, h = up × n, v = n × h (as the
// keypoints' wall frame).
struct ZoneWall {
    Eigen::Vector3d normal, horizontal, vertical;
    // The directions as rows: (normal, h, v) of a project-frame vector.
    Eigen::Matrix3d rows() const {
        Eigen::Matrix3d M;
        M.row(0) = normal.transpose(), M.row(1) = horizontal.transpose(),
        M.row(2) = vertical.transpose();
        return M;
    }
};
ZoneWall zone_wall(const VectorReference& reference, std::size_t zone,
                   const Eigen::Vector3d& design_normal);

// The zone rows: vector_count (value: areas with a vector, n: the zone's areas) always; with
// at least one vector, the zone's vector — the mean of its areas' vectors, Σ = Σ_k (Σ_k + T)
// / n² (the fits' and the zone's between-area variance T) + Σ_T at the zone — as
// vector_dx_m, _dy_m, _dz_m
// (project frame) and vector_along_normal_m, _along_surface_h_m, _along_surface_v_m (the
// zone's wall), each with LoD95 = 1.96 σ along its direction; significant beyond it.
std::vector<ZoneResult> vector_zone_results(const VectorConfig& config,
                                            const VectorReference& reference,
                                            const VectorEpoch& epoch);

// The per-area float32 arrays: vector_x_m, _y_m, _z_m (the area's centroid), vector_dx_m,
// _dy_m, _dz_m and vector_sigma_x_m, _y_m, _z_m (with the between-area variance and the
// registration's); NaN where the
// area has no vector.
std::vector<CorePointArray> vector_area_arrays(const VectorReference& reference,
                                               const VectorEpoch& epoch);

// The stage: runs when enabled with at least one zone (site_stages).
class VectorStage final : public Stage {
  public:
    explicit VectorStage(VectorConfig config) : config_(std::move(config)) {}
    const char* name() const override { return "vectors"; }
    StageVerdict run(StageContext& ctx) const override;
    // The product from the reference's supervoxels, through `cache`.
    std::shared_ptr<const VectorReference> reference(ReferenceEpoch& reference,
                                                     ReferenceCache& cache) const;

  private:
    VectorConfig config_;
};

}  // namespace tlsmon
