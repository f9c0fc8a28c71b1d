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
// in metres; `face` selects an independent pattern per face.
double concrete_albedo(const Texture& t, int face, double u, double v);

// Ground (gravel and grass) albedo at project (x, y).
double ground_albedo(const Texture& t, double x, double y);

}  // namespace tlsmon::sim
