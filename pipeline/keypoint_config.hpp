#pragma once
// What the keypoint stage needs of the site: the keypoint parameters ([keypoints],
// docs/configuration.md) and the zones it measures in (docs/keypoints.md).
#include <string>
#include <vector>

#include "algorithms/zones/zone_shape.hpp"

namespace tlsmon {

// The segments a displacement is given for: the configured zones, or bands of the vertical
// angle (the case study's).
enum class KeypointSegments { zones, bands };

struct KeypointConfig {
    bool enabled = true;  // zones: runs when there is at least one zone; bands: always
    // AKAZE, not KAZE: the one that keeps a pier epoch within 10 s on 2 cores
    // (docs/keypoints.md, "The default detector").
    std::string detector = "akaze";
    std::string descriptor = "brisk";
    bool clahe = false;
    double window_deg = 0.05;  // angular radius of the matching window
    // Least-squares refinement of each match on a patch of (2·patch_radius + 1)² pixels
    // (algorithms/keypoints/patch_refinement.hpp).
    bool refine = true;
    int patch_radius = 7;
    double ratio = 0.0;  // Lowe's ratio test; 0: off
    bool mutual = false;
    double mad_k = 2.0;    // outlier filters: |x − median| > k · 1.4826 · MAD
    int min_matches = 10;  // kept matches a segment needs
    // Zones: a match whose beam meets the zone's wall at a larger angle to its normal is not
    // used (a grazing surface's image is stretched along the beam; its keypoints do not
    // repeat). 90: every match.
    double max_incidence_deg = 75.0;
    // m: a segment where the scan samples the surface coarser than this (the median over its
    // matches of range × angular step) is undefined: its intensity image is aliased, the
    // sub-pixel positions follow the lattice, not the surface (docs/keypoints.md, "Sampling").
    double max_sample_spacing = 0.015;
    KeypointSegments segments = KeypointSegments::zones;
    double band_width_deg = 5.0;
    double registration_error = 0.0;  // m, the LoD's reg without a registration
    // The zone quantities modelled by d(t, z) each epoch.
    std::vector<std::string> model_quantities{"keypoint_along_surface_h_m",
                                              "keypoint_along_surface_v_m"};
    std::vector<ZoneShape> zones;
};

}  // namespace tlsmon
