#pragma once
// The deformation field of the pier: one source of truth for the renderer (which moves the
// surface) and the truth file (which reports it).
//
// Thermal bending (simulator/weather.hpp gives the section's side temperatures, lagged behind
// the sunlit and shaded faces): a linear temperature difference ΔT across a section of depth
// b bends it to a constant curvature κ = α_T·ΔT/b, and a cantilever of height H with
// constant curvature deflects u(z) = κ z²/2, u_top = κ H²/2. Per axis, the top moving away
// from the warmer face:
//   ΔT_x = T_west − T_east,   κ_x = α_T ΔT_x / (x1 − x0)
//   ΔT_y = T_south − T_north, κ_y = α_T ΔT_y / (y1 − y0)
//   u_h(z) = (κ_x, κ_y) H²/2 · (z/H)^p          p = exponent (2: the exact cantilever)
//   u_z(z) = α_T (T̄ − T_ref) z                  T̄ the mean of the four sides
// plus, from the step event's epoch on, a constant step vector for z_min ≤ z ≤ z_max, and
// from the tilt event's epoch on a rigid rotation ω about the foot's centre f (small angle:
// u = ω × (p − f), ω = (−θ_y, θ_x, 0), so the axis leans θ_x towards +x, θ_y towards +y).
// The ground and the targets never move (a knocked target is an event of its own).
#include <Eigen/Core>

#include "simulator/scene.hpp"
#include "simulator/weather.hpp"

namespace tlsmon::sim {

struct ThermalBending {
    Eigen::Vector2d delta_driving = Eigen::Vector2d::Zero();  // K, (ΔT_x, ΔT_y) of the faces
    Eigen::Vector2d delta_lagged = Eigen::Vector2d::Zero();   // K, of the section (lag τ)
    double mean_change = 0.0;                                 // K, T̄ − T_ref
    Eigen::Vector2d curvature = Eigen::Vector2d::Zero();      // 1/m, (κ_x, κ_y)
    Eigen::Vector3d top = Eigen::Vector3d::Zero();            // m, u at the top; 0 when disabled
};
ThermalBending thermal_bending(const Site& site, const ThermalState& state);

// The field at one epoch (the renderer calls it a few times per sub-ray); gives the same
// numbers as pier_displacement.
class PierDisplacementField {
  public:
    PierDisplacementField(const Site& site, int epoch, const ThermalBending& bending);
    Eigen::Vector3d operator()(const Eigen::Vector3d& p) const;

  private:
    const Site* site_;
    bool stepped_;
    Eigen::Vector2d tilt_ = Eigen::Vector2d::Zero();  // rad, (θ_x, θ_y); 0 before the event
    Eigen::Vector3d top_;
};

// The tilt event's rotation at `epoch`, rad (θ_x, θ_y); zero before it or without one.
Eigen::Vector2d pier_tilt(const Site& site, int epoch);

// Displacement of the pier's material point `p` (undeformed position, project frame) at
// `epoch` with the epoch's bending. Zero when deformation is disabled; the caller decides
// that `p` belongs to the pier.
Eigen::Vector3d pier_displacement(const Site& site, const Eigen::Vector3d& p, int epoch,
                                  const ThermalBending& bending);

// True centre of target `index` at `epoch` (moved by the knocked-target event).
Eigen::Vector3d target_centre(const Site& site, std::size_t index, int epoch);

}  // namespace tlsmon::sim
