#pragma once
// The parameters of the keypoint displacement method (docs/keypoints.md) that a user sets,
// with their defaults in this one place: the site's [keypoints] section embeds them and
// `tlsmon keypoints` starts from them. The kernel's parts (features, matching, outlier
// filters, segments) take their defaults from here.
#include <string>

namespace tlsmon::keypoints {

struct Parameters {
    // AKAZE, not KAZE: the one that keeps a pier epoch within 10 s on 2 cores
    // (docs/keypoints.md, "The default detector").
    std::string detector = "akaze";
    std::string descriptor = "brisk";
    bool clahe = false;
    // The KAZE/AKAZE detector's response threshold (the Hessian determinant of the image
    // scaled to 0..1). OpenCV's 0.001 finds few keypoints where the beam's footprint blurs the
    // texture (a far zone); 0.0003 keeps the matches there whose least-squares refinement
    // still measures (docs/keypoints.md, "The detector's threshold").
    double detector_threshold = 0.0003;
    // The matching window (keypoint_matching.hpp): its angular radius, and the largest
    // displacement expected at the object, which widens it near the scanner (0.02 m is
    // 0.38° at 3 m, under the angle beyond 23 m).
    double window_deg = 0.05;
    double window_m = 0.02;
    // Least-squares refinement of each match on a patch of (2·patch_radius + 1)² pixels
    // (patch_refinement.hpp).
    bool refine = true;
    int patch_radius = 7;
    // σ of the Gaussian both images are smoothed with before the refinement, pixels
    // (patch_refinement.hpp: it keeps the lattice's aliasing out of the shift).
    double prefilter_px = 1.5;
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
    double band_width_deg = 5.0;      // bands of the vertical angle, when they are the segments
    double registration_error = 0.0;  // m, the LoD's reg without a registration
};

}  // namespace tlsmon::keypoints
