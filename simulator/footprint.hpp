#pragma once
// The beam footprint as a fixed pattern of sub-rays: the central ray and six rays on a ring
// at the footprint's 1/e² radius, weighted so that the pattern has the second moment of the
// Gaussian profile I(ρ) ∝ exp(−2ρ²/w²) (E[ρ²] = w²/2: centre 1/2, ring 1/12 each). The
// pattern is the same for every cell, so the render needs no random numbers for it.
//
// A cell's return is the integral over the footprint (Lichti & Jamtsho 2006, "Angular
// resolution of terrestrial laser scanners"): the intensity is the weighted reflectance,
// and a phase-based instrument measures the signal-weighted mean of the ranges it sees
// (the "mixed pixel" of a footprint that straddles an edge, Hebert & Krotkov 1992).
#include <array>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct SubRay {
    double across = 0.0, up = 0.0;  // offset in units of the 1/e² radius w
    double weight = 0.0;            // the pattern's weights sum to 1
};

constexpr std::size_t kSubRays = 7;
// Sub-ray 0 is the central ray.
const std::array<SubRay, kSubRays>& footprint_pattern();

// 1/e² radius of the footprint at range r, m: (exit_diameter + divergence · r) / 2.
double footprint_radius(const Beam& beam, double range);

// Angular 1/e² radius seen from the scanner at range r, rad (footprint_radius / r).
double footprint_angle(const Beam& beam, double range);

// Footprints whose sub-rays meet different surfaces at ranges more than this apart are
// counted as mixed pixels (in the truth).
constexpr double kMixedPixelSpread = 0.10;  // m

}  // namespace tlsmon::sim
