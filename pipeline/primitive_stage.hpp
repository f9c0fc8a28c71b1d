#pragma once
// Stage "primitives": the geometric primitive each zone names (a round pier's cylinder, a
// plane, a sphere), fitted in every epoch in the reference's frame, and the change of its
// parameters against the reference's fit tested with the full covariance (docs/
// primitives.md; the thesis on rigid patches in TLS point clouds, §5.2).
//
// Reference product (the reference cache, stage "primitives"): per zone, RANSAC on the
// reference's points in the zone thinned with normals (pipeline/primitive_seed.hpp), then
// the fine fit on all of them (algorithms/primitives/primitive_fit.hpp).
//
// Each epoch: its points mapped into the reference frame (epoch_to_reference, as M3C2),
// those in the zone fitted from the reference's primitive, and the change Δx with Σ_Δ =
// Σ_reference + Σ_epoch + J·Σ_T·Jᵀ (algorithms/primitives/primitive_change.hpp; Σ_T zero
// without a registration: the epoch then carries that quality and raises no alarm).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "algorithms/primitives/primitive_change.hpp"
#include "pipeline/primitive_config.hpp"
#include "pipeline/primitive_reference.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

// The zone quantities the stage writes (the alarm rules name them). A cylinder: the tilt of
// its axis (the χ² test of both components; its LoD the tilt that would be significant in the
// direction measured), its lean towards the frame's b1 and b2 (the project's x and y for a
// standing column), the axis's displacement at the zone's far end along b1 and b2, the radius
// change. A plane: the tilt of its normal, its offset along the normal. A sphere: the
// displacement of its centre (χ², 3 components) and each component, the radius change.
inline constexpr std::array<const char*, 15> kPrimitiveQuantities = {"cylinder_tilt_arcsec",
                                                                     "cylinder_lean_x_arcsec",
                                                                     "cylinder_lean_y_arcsec",
                                                                     "cylinder_top_x_m",
                                                                     "cylinder_top_y_m",
                                                                     "cylinder_radius_change_m",
                                                                     "fitted_plane_tilt_arcsec",
                                                                     "fitted_plane_offset_m",
                                                                     "sphere_displacement_m",
                                                                     "sphere_dx_m",
                                                                     "sphere_dy_m",
                                                                     "sphere_dz_m",
                                                                     "sphere_radius_change_m",
                                                                     "primitive_s0",
                                                                     "primitive_rms_m"};

// The canonical text of every parameter the reference product depends on (its cache key).
std::string primitives_reference_parameters(const PrimitivesConfig& config);

PrimitiveReference prepare_primitives_reference(const PrimitivesConfig& config,
                                                const std::vector<Scan>& scans);

struct PrimitiveEpoch {
    std::vector<primitives::Fit> fits;        // per reference entry; status fitted when measured
    std::vector<primitives::Change> changes;  // per entry; empty delta when not measured
};

PrimitiveEpoch measure_primitives(const PrimitivesConfig& config,
                                  const PrimitiveReference& reference,
                                  const std::vector<Scan>& scans, const StageOutputs& outputs);

// A cylinder's top, at `far_end` along its axis, from the change of its parameters
// (x, y, θx, θy, r): Δs + L·Δθ, the Jacobian of `cylinder_top_x_m`, `cylinder_top_y_m`.
Eigen::Matrix<double, 2, 5> cylinder_top_jacobian(double far_end);

// The zone rows of the quantities above for each measured zone.
std::vector<ZoneResult> primitive_zone_results(const PrimitivesConfig& config,
                                               const PrimitiveReference& reference,
                                               const PrimitiveEpoch& epoch);

class PrimitivesStage final : public Stage {
  public:
    explicit PrimitivesStage(PrimitivesConfig config) : config_(std::move(config)) {}
    const char* name() const override { return "primitives"; }
    StageVerdict run(StageContext& ctx) const override;
    std::shared_ptr<const PrimitiveReference> reference(ReferenceEpoch& reference,
                                                        ReferenceCache& cache) const;

  private:
    PrimitivesConfig config_;
};

}  // namespace tlsmon
