#include "pipeline/pbm3c2_config.hpp"

namespace tlsmon {

std::vector<SectionKey<PbM3c2Config>> pbm3c2_keys() {
    using K = Keys<PbM3c2Config>;
    return {
        K::flag(&PbM3c2Config::enabled, "enabled",
                "Run patch-based M3C2 (docs/pbm3c2.md) for every epoch: the distance between "
                "the reference's and the epoch's plane on each supervoxel of the reference "
                "inside a zone. The supervoxels are those of the registration on stable areas "
                "(`registration.stable_voxel`, `stable_seed`), built once."),
        K::number(&PbM3c2Config::search_depth, "search_depth", 0.001, 10, "m",
                  "A point belongs to a patch when it projects into the patch's footprint within "
                  "this of the reference plane along its normal: the largest change measured."),
        K::integer(&PbM3c2Config::min_points, "min_points", 4, 1000000, "",
                   "Points each epoch needs on a patch for its plane; fewer: no distance there "
                   "(NaN, not counted in the zone's values)."),
        K::number(&PbM3c2Config::max_roughness, "max_roughness", 0.0001, 1, "m",
                  "A patch whose reference points lie farther than this (RMS) from their plane "
                  "is not one plane (an edge, a corner, clutter): no distance there."),
        K::number(&PbM3c2Config::max_incidence_deg, "max_incidence_deg", 1, 90, "°",
                  "A patch seen at a larger angle between its normal and the line of sight from "
                  "the reference's scanner is left out: on a grazing face a plane's place along "
                  "its normal rests on the beam's angle and footprint more than on its range."),
        K::integer(&PbM3c2Config::threads, "threads", 0, 256, "",
                   "Threads of the stage; 0: every core."),
    };
}

}  // namespace tlsmon
