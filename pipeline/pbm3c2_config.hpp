#pragma once
// What the patch-based M3C2 stage needs of the site: the method's parameters ([pbm3c2],
// docs/configuration.md; their defaults are the kernel's, algorithms/patches/parameters.hpp),
// the zones whose patches it aggregates, and the segmentation that gives the patches (the
// [registration] stable_voxel and stable_seed keys: one segmentation for both).
#include <vector>

#include "algorithms/patches/parameters.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/config_key.hpp"
#include "pipeline/stable_area_config.hpp"

namespace tlsmon {

struct PbM3c2Config : patches::Parameters {
    bool enabled = false;  // runs when enabled, with at least one zone
    std::vector<ZoneShape> zones;
    StableAreaConfig segmentation;  // set from [registration] by pipeline_config
};

// The keys of [pbm3c2] (core/config_key.hpp).
std::vector<SectionKey<PbM3c2Config>> pbm3c2_keys();

}  // namespace tlsmon
