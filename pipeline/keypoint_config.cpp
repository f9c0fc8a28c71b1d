#include "pipeline/keypoint_config.hpp"

#include <array>

namespace tlsmon {

namespace {

constexpr std::array<Named<KeypointSegments>, 2> kKeypointSegments{{
    {KeypointSegments::zones, "zones"},
    {KeypointSegments::bands, "bands"},
}};

}  // namespace

std::vector<SectionKey<KeypointConfig>> keypoint_keys() {
    using K = Keys<KeypointConfig>;
    return {
        K::flag(&KeypointConfig::enabled, "enabled",
                "Run the keypoint displacement method (docs/keypoints.md) for every epoch against "
                "the reference epoch: movement along the surface, which M3C2 does not see. With "
                "`segments = \"zones\"` it needs at least one `[[zone]]`; an epoch without a "
                "structured scan (PTX, gridded E57) is not measured by it."),
        K::text(&KeypointConfig::detector, "detector", "`akaze`, `kaze`, `sift`, `brisk`, `orb`",
                "Keypoint detector in the intensity images. `akaze` keeps a pier epoch within 10 s "
                "on 2 cores; `kaze` (the Hessian response of the case study's SURF) takes about "
                "three times as long for the same accuracy (docs/keypoints.md)."),
        K::text(&KeypointConfig::descriptor, "descriptor",
                "`brisk`, `sift`, `orb`; `kaze`/`akaze` on their own detector only",
                "Keypoint descriptor; binary ones are matched by Hamming distance."),
        K::number(&KeypointConfig::detector_threshold, "detector_threshold", 1e-6, 1, "",
                  "`kaze`/`akaze`: the detector's response threshold (the Hessian determinant of "
                  "the intensity image scaled to 0..1). Lower finds more keypoints where the "
                  "beam's footprint blurs the texture, far from the scanner; the matches' own "
                  "standard error stays honest down to about 0.0003 (docs/keypoints.md, \"The "
                  "detector's threshold\")."),
        K::flag(&KeypointConfig::clahe, "clahe",
                "Equalise the 8-bit intensity image (CLAHE) before detection and description."),
        K::number(&KeypointConfig::window_deg, "window_deg", 0.0001, 5, "°",
                  "Matching window: an epoch keypoint is a candidate for a reference keypoint "
                  "within this angle of it; the nearest descriptor wins. The floor of the "
                  "window, and its radius wherever window_m / range is smaller."),
        K::number(&KeypointConfig::window_m, "window_m", 0, 1, "m",
                  "The largest displacement expected at the object between the reference and "
                  "an epoch: the window of a keypoint at range r is at least window_m / r, so a "
                  "motion near the scanner is matched whole; 0: the angle alone."),
        K::flag(&KeypointConfig::refine, "refine",
                "Refine each match by least-squares matching of the reference's intensity patch "
                "around the keypoint's nearest pixel (docs/keypoints.md): the detector's sub-pixel "
                "position follows the pixel lattice, which moves over the surface as the scanner "
                "drifts."),
        K::integer(&KeypointConfig::patch_radius, "patch_radius", 2, 50, "px",
                   "The refinement's patch: (2 · radius + 1)² pixels."),
        K::number(&KeypointConfig::prefilter_px, "prefilter_px", 0, 5, "px",
                  "σ of the Gaussian both intensity images are smoothed with before the "
                  "refinement: the lattice's aliasing, fixed to the scanner's pixels, would "
                  "otherwise pull every shift of a zone the same way as the scanner drifts "
                  "(docs/keypoints.md); 0: none."),
        K::number(&KeypointConfig::ratio, "ratio", 0, 1, "",
                  "Lowe's ratio test among the candidates (best < ratio · second best); 0: off."),
        K::flag(&KeypointConfig::mutual, "mutual",
                "Keep a match only when it is also the epoch keypoint's best in the reference."),
        K::number(&KeypointConfig::mad_k, "mad_k", 0.5, 10, "",
                  "Outlier filters: a match is removed when a quantity lies farther than "
                  "k · 1.4826 · MAD from the segment's median (the method's k = 2)."),
        K::integer(&KeypointConfig::min_matches, "min_matches", 3, 1000000, "",
                   "Matches a segment needs after the filters; fewer: undefined."),
        K::number(&KeypointConfig::max_incidence_deg, "max_incidence_deg", 0, 90, "°",
                  "`segments = \"zones\"`: a match whose beam meets the zone's wall (its plane "
                  "fitted to the reference's points) at a larger angle to the normal is not used: "
                  "a grazing wall's image is stretched along the beam and its keypoints do not "
                  "repeat (the simulated pier's west face, 87°). 90: every match."),
        K::number(&KeypointConfig::max_sample_spacing, "max_sample_spacing", 0.0001, 1, "m",
                  "A segment the scan samples coarser than this (the median over its matches of "
                  "range × angular step) is undefined: its intensity image is aliased and the "
                  "sub-pixel positions follow the scan's lattice (docs/keypoints.md, "
                  "\"Sampling\"). About the beam's footprint at the structure's range."),
        K::choice(&KeypointConfig::segments, "segments", kKeypointSegments,
                  "`zones`: one displacement per `[[zone]]` (the zones M3C2 uses), detection "
                  "confined to them. `bands`: per band of the vertical angle, zones named "
                  "`keypoint_band_<lo>_<hi>`, detection in the whole image."),
        K::number(&KeypointConfig::band_width_deg, "band_width_deg", 0.1, 180, "°",
                  "Width of the vertical-angle bands (`segments = \"bands\"`)."),
        K::number(&KeypointConfig::registration_error, "registration_error", 0, 1, "m",
                  "The LoD's registration term when there is no registration (no `[[target]]`). "
                  "With a registration each segment gets the registration's σ at its centroid "
                  "along each figure's direction."),
        K::names(&KeypointConfig::model_quantities, "model_quantities",
                 "keypoint displacement quantities, no repeats",
                 "The zone quantities the displacement model d(t, z) is refitted for each epoch, "
                 "over every segment and epoch so far (`tlsmon query keypoint-models`)."),
    };
}

}  // namespace tlsmon
