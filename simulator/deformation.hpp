#pragma once
// The deformation field of the pier: one source of truth for the renderer (which moves the
// surface) and the truth file (which reports it).
//
// Thermal bending (solar heating of one face gives a temperature gradient across the
// section, i.e. a nearly constant curvature, so a cantilever's deflection grows as z²):
//   s(t)    = (1 − cos(π t / T_peak)) / 2                    smooth, 0 at t = 0, 1 at T_peak
//   u_h(z,t) = D_top · (z / H)^p · s(t) · (cos α, sin α, 0)   horizontal, p = 2 by default
//   u_z(z,t) = E_top · (z / H) · s(t)                         uniform vertical extension
// plus, from the step event's epoch on, a constant step vector for z_min ≤ z ≤ z_max.
// The ground and the targets never move (a knocked target is an event of its own).
#include <Eigen/Core>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

// s(t) above, t in hours since the first epoch.
double thermal_time_factor(const Deformation& d, double hours);

// The field at one epoch with its time factor and direction evaluated once (the renderer
// calls it a few times per sub-ray); gives the same numbers as pier_displacement.
class PierDisplacementField {
  public:
    PierDisplacementField(const Site& site, int epoch, double hours);
    Eigen::Vector3d operator()(const Eigen::Vector3d& p) const;

  private:
    const Site* site_;
    bool stepped_;
    double s_ = 0.0, cos_a_ = 1.0, sin_a_ = 0.0;
};

// Displacement of the pier's material point `p` (undeformed position, project frame) at
// `epoch`, `hours` after the first epoch. Zero when deformation is disabled; the caller
// decides that `p` belongs to the pier.
Eigen::Vector3d pier_displacement(const Site& site, const Eigen::Vector3d& p, int epoch,
                                  double hours);

// True centre of target `index` at `epoch` (moved by the knocked-target event).
Eigen::Vector3d target_centre(const Site& site, std::size_t index, int epoch);

}  // namespace tlsmon::sim
