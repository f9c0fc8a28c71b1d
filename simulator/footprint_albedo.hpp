#pragma once
// The reflectance a beam's footprint sees on one surface: the surface's texture convolved
// with the beam's Gaussian profile (σ = w/2, footprint.hpp) at the footprint's centre.
// Exact for the checkerboards and the formwork joints, a blurred edge for the tie holes
// (texture.hpp); the other surfaces' reflectance is smooth at the footprint's scale and is
// taken at the hit.
#include "simulator/ray_cast.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

double footprint_albedo(const Hit& centre, const Texture& texture, double blur);

}  // namespace tlsmon::sim
