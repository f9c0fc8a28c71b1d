#pragma once
// Deterministic surface reflectance ("albedo", 0..1) of the scene, so that the intensity
// image of a scan has the structure image keypoints need on real concrete: value noise at
// several scales (aggregate, patches, weathering), formwork panel joints, tie holes left by
// the formwork ties, and vertical run-off stains. Evaluated at the material point of the
// surface, so the pattern moves with the deforming pier.
#include <cstdint>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

// Smooth value noise in [0, 1] on a unit lattice (bilinear with smoothstep weights over
// hashed lattice values).
double value_noise(std::uint64_t seed, double u, double v);

// Concrete albedo on a pier face: u runs horizontally along the face, v = z (height), both
// in metres; `face` selects an independent pattern per face. `blur` > 0: the sharp-edged
// features (formwork joints, tie holes) convolved with an isotropic Gaussian of that
// standard deviation, m, as a beam's footprint sees them (simulator/footprint.hpp); the
// value noise and stains, smooth at that scale, are left as they are.
double concrete_albedo(const Texture& t, int face, double u, double v, double blur = 0.0);

// A 2×2 checkerboard target at in-plane coordinates (a across, b up) from its centre:
// white where a and b have the same sign. `blur` > 0: convolved with an isotropic Gaussian,
// exactly, since the pattern is separable: m + h · erf(a / √2σ) · erf(b / √2σ).
constexpr double kCheckerWhite = 0.85, kCheckerBlack = 0.05;
double checkerboard_albedo(double a, double b, double blur = 0.0);

// Ground (gravel and grass) albedo at project (x, y).
double ground_albedo(const Texture& t, double x, double y);

}  // namespace tlsmon::sim
