#pragma once
// Range noise σ_r of one return.
//
// `constant`: σ = a + b·r, whatever the return's strength (the earlier model).
// `signal`: a phase-based rangefinder's phase noise falls with the signal-to-noise ratio;
// shot-noise limited, σ ∝ 1/√P (Wehr & Lohr 1999), and the power returned by an extended
// Lambertian surface filling the beam is P ∝ ρ·|cos α| / r² (laser radar equation, Jelalian
// 1992). Hence σ = a_s + b_s · r / √(ρ·|cos α|), with a floor a_s (electronics,
// quantisation) that dominates on bright, near surfaces.
#include "simulator/scene.hpp"

namespace tlsmon::sim {

// `signal` is ρ·|cos α| of the return (footprint-weighted reflectance times the cosine of
// the incidence angle), `range` in metres; σ in metres.
double range_sigma(const Noise& noise, double range, double signal);

}  // namespace tlsmon::sim
