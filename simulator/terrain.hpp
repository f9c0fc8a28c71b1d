#pragma once
// The ground of the site: a valley cross-section z = h(y) (piecewise linear through the
// profile points, level beyond the ends, the same for every x) and stable blocks on it
// (a pier foundation, an abutment). Neither ever moves.
//
// A scanner on a tripod 1.5 m above flat ground sees the ground at 175 m at 0.5° grazing:
// ρ·cos α ≈ 0.2 · 0.009, a return far below `min_return`. On a real site the scanner stands
// on a terrace or slope above the valley floor and the far side rises; the profile models
// both, and its ray intersection stays exact and cheap (a ray against each linear piece is
// one division, about ten pieces at most).
#include <Eigen/Core>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

// Ground height h(y), m.
double terrain_height(const Terrain& terrain, double y);

// Height a support stands on at (x, y): the top of the highest block whose footprint holds
// (x, y), else the ground. `block` is set to that block's index or −1.
double support_height(const Terrain& terrain, double x, double y, int* block = nullptr);

// Nearest crossing of the ray o + t·d (d unit) from above the ground down into it, with t in
// (0, t_max); infinity if none. `normal` is the upward unit normal there. `creep`: the creeping
// patch's displacement at this epoch (terrain.creep); `material` is then set to the hit's
// point on the unmoved ground (for its texture).
double intersect_terrain(const Terrain& terrain, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                         double t_max, Eigen::Vector3d& normal,
                         const Eigen::Vector3d& creep = Eigen::Vector3d::Zero(),
                         Eigen::Vector3d* material = nullptr);

// Ground reflectance at (x, y): soil, grass and gravel patches about the mean
// `terrain.albedo` (0.1–0.3 at the 1.5 µm of a phase-based scanner), two scales of texture.
double terrain_albedo(const Texture& texture, const Terrain& terrain, double x, double y);

// Throws tlsmon::Error when the profile is not increasing in y or the arrays differ in size,
// or a block is empty.
void validate_terrain(const Terrain& terrain);

}  // namespace tlsmon::sim
