#pragma once
// The reference's patches inside the zones (docs/pbm3c2.md, "Patches"): the supervoxels of the
// registration on stable areas — segmented once, shared by every stage that works on patches
// (patch-based M3C2, the 3-D vectors) — that are patches of plane seen from the scanner, each
// with its frame and footprint and the zones it belongs to.
#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/patches/patch_index.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "pipeline/stable_area_registration.hpp"

namespace tlsmon {

struct ZonePatches {
    std::vector<patches::Patch> patches;    // frame (normal towards the scanner), footprint
    std::vector<std::uint32_t> supervoxel;  // per patch: its supervoxel of the reference
    std::vector<std::string> zone_names;    // in the configuration's order
    std::vector<std::vector<std::uint32_t>> zone_patches;  // per zone, its patches (ascending)
};

// The supervoxels that are patches of plane as the registration on stable areas takes them
// (without its roughness limit: the stage's own decides), seen at no more than
// `max_incidence_deg` from `supervoxels.viewpoint`, whose centroid lies in a zone and, for a
// zone with a design normal, whose normal lies within 30° of it (a soffit or the ground in a
// face's box is not that face).
ZonePatches zone_patches(const StableAreaConfig& segmentation,
                         const ReferenceSupervoxels& supervoxels,
                         const std::vector<ZoneShape>& zones, double max_incidence_deg);

}  // namespace tlsmon
