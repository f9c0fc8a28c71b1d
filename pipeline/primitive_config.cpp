#include "pipeline/primitive_config.hpp"

#include <algorithm>

namespace tlsmon {

primitives::FitParameters PrimitivesConfig::fit_parameters() const {
    primitives::FitParameters p;
    p.band = band;
    p.max_incidence_deg = max_incidence_deg;
    p.clip_k = clip_k;
    p.min_points = static_cast<std::size_t>(min_points);
    p.threads = static_cast<unsigned>(std::max(0, threads));
    return p;
}

std::vector<SectionKey<PrimitivesConfig>> primitives_keys() {
    using K = Keys<PrimitivesConfig>;
    return {
        K::flag(&PrimitivesConfig::enabled, "enabled",
                "Fit the primitive each `[[zone]]` names (`primitive = \"cylinder\"`, `\"plane\"` "
                "or `\"sphere\"`) in every epoch and test the change of its parameters against the "
                "reference epoch's (docs/primitives.md); without such a zone it does not run."),
        K::number(&PrimitivesConfig::sample_voxel, "sample_voxel", 0.001, 10, "m",
                  "The reference's points in the zone are thinned to one per cube of this edge "
                  "for the RANSAC that finds the primitive (once, with the reference epoch)."),
        K::number(&PrimitivesConfig::normal_radius, "normal_radius", 0.01, 10, "m",
                  "The thinned sample's normals (for RANSAC) from the neighbours within this."),
        K::number(&PrimitivesConfig::ransac_threshold, "ransac_threshold", 0.0001, 1, "m",
                  "A sample point within this of a RANSAC model counts for it."),
        K::integer(&PrimitivesConfig::ransac_iterations, "ransac_iterations", 10, 1000000, "",
                   "RANSAC's samples."),
        K::number(&PrimitivesConfig::band, "band", 0.001, 10, "m",
                  "The fine fit takes every point of the zone within this of the primitive it "
                  "starts from (RANSAC's, then the reference's): the largest change measured."),
        K::number(&PrimitivesConfig::max_incidence_deg, "max_incidence_deg", 1, 90, "°",
                  "Points seen at a larger angle between the surface normal and the beam are "
                  "left out: a cylinder's silhouette, where returns mix and ranges bias."),
        K::number(&PrimitivesConfig::clip_k, "clip_k", 1.5, 100, "",
                  "A point farther from the primitive than this many σ (its σ along the normal "
                  "from [station], times the robust scale of all when larger) is a stray return "
                  "and left out."),
        K::integer(&PrimitivesConfig::min_points, "min_points", 10, 100000000, "",
                   "Points a fit needs; fewer: no values for the zone in that epoch."),
        K::number(&PrimitivesConfig::alpha, "alpha", 0.0001, 0.5, "",
                  "Level of the tests of a change (χ² of the tilt, displacement; normal of each "
                  "component): a change is significant beyond its LoD at this level."),
        K::integer(&PrimitivesConfig::threads, "threads", 0, 256, "",
                   "Threads of the stage; 0: every core."),
    };
}

}  // namespace tlsmon
