#pragma once
// What the keypoint stage needs of the site: the method's parameters ([keypoints],
// docs/configuration.md; their defaults are the kernel's, algorithms/keypoints/parameters.hpp)
// and the zones it measures in (docs/keypoints.md).
#include <string>
#include <vector>

#include "algorithms/keypoints/parameters.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/config_key.hpp"
#include "core/scanner_noise.hpp"

namespace tlsmon {

// The segments a displacement is given for: the configured zones, or bands of the vertical
// angle (the case study's).
enum class KeypointSegments { zones, bands };

struct KeypointConfig : keypoints::Parameters {
    bool enabled = true;  // zones: runs when there is at least one zone; bands: always
    KeypointSegments segments = KeypointSegments::zones;
    // The zone quantities modelled by d(t, z) each epoch.
    std::vector<std::string> model_quantities{"keypoint_along_surface_h_m",
                                              "keypoint_along_surface_v_m"};
    std::vector<ZoneShape> zones;
    // The site's scanner model ([station], set by pipeline_config): the outlier filters'
    // noise floor.
    ScannerNoise noise;
};

// The keys of [keypoints] (core/config_key.hpp).
std::vector<SectionKey<KeypointConfig>> keypoint_keys();

}  // namespace tlsmon
