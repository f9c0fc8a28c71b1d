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
// Sub-ray 0 is the central ray; 1–6 the hexagon at 30°, 90°, …, 330° from `across`.
const std::array<SubRay, kSubRays>& footprint_pattern();

// The adaptive render casts the centre and a triangle of the ring first (30°, 150°, 270°);
// if they all meet one surface the footprint is those four, weighted 1/2 and 1/6 each (the
// same second moment E[ρ²] = w²/2, and the same profile across and along the beam's
// horizontal axis), otherwise the other three are cast and the hexagon is used.
constexpr std::array<std::size_t, 3> kTriangle{1, 3, 5};
constexpr std::array<std::size_t, 3> kTriangleComplement{2, 4, 6};
constexpr double triangle_weight(std::size_t k) {
    return k == 0 ? 0.5 : (k % 2 == 1 ? 1.0 / 6.0 : 0.0);
}

// 1/e² radius of the footprint at range r, m: (exit_diameter + divergence · r) / 2.
double footprint_radius(const Beam& beam, double range);

// Angular 1/e² radius seen from the scanner at range r, rad (footprint_radius / r).
double footprint_angle(const Beam& beam, double range);

// Footprints whose sub-rays meet different surfaces at ranges more than this apart are
// counted as mixed pixels (in the truth).
constexpr double kMixedPixelSpread = 0.10;  // m

}  // namespace tlsmon::sim
