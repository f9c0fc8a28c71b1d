#pragma once
// The truth's record of the scene around the pier at one epoch: the terrain and its stable
// blocks, each target's mount and supports, which occluders stood where, the vegetation,
// how much of each target the occluders hid, and the points per surface kind.
#include <nlohmann/json.hpp>

#include "simulator/render.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

// Rays from the station to a target: the centre and eight points around it (at 0.7 of the
// radius across the line of sight for a sphere, at ±0.35 of the side for a board).
struct TargetSightlines {
    int rays = 0;
    int reach = 0;     // the target is the first surface met
    int occluded = 0;  // an occluder or vegetation is met first
};
TargetSightlines target_sightlines(const SceneAtEpoch& scene, std::size_t target);

// Adds `terrain`, `occlusion`, and per target `mount`, `base_z`, `supports`, and (with a
// rendered scan) `scan.points_by_surface` to the truth `j` (docs/simulator.md).
void add_scene_truth(nlohmann::json& j, const Site& site, int epoch, double hours,
                     const RenderedScan* rendered);

}  // namespace tlsmon::sim
