#pragma once
// What the 3-D vector stage needs of the site ([vectors], docs/configuration.md;
// docs/vectors.md): the measuring window on each of the reference's patches inside the zones,
// the local registration's parameters (algorithms/vectors/area_registration.hpp), and the
// segmentation that gives the patches (the [registration] stable_voxel and stable_seed keys:
// one segmentation for the registration, patch-based M3C2 and the vectors).
#include <vector>

#include "algorithms/vectors/area_registration.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/config_key.hpp"
#include "pipeline/stable_area_config.hpp"

namespace tlsmon {

struct VectorConfig : vectors::Parameters {
    bool enabled = false;  // runs when enabled, with at least one zone
    // m: the side of the square measured about each patch's centroid (its area), in the
    // patch's plane; the patch's points within `search_depth` of the plane.
    double window = 1.0;
    double search_depth = 0.10;
    double max_incidence_deg = 75.0;  // °: patches seen more obliquely are left out
    int threads = 0;                  // 0: every core
    std::vector<ZoneShape> zones;     // set from the [[zone]] tables by pipeline_config
    StableAreaConfig segmentation;    // set from [registration] by pipeline_config
};

// Throws Error naming the parameter when a value cannot give a meaningful result.
void validate(const VectorConfig& config);

// The keys of [vectors] (core/config_key.hpp).
std::vector<SectionKey<VectorConfig>> vector_keys();

}  // namespace tlsmon
