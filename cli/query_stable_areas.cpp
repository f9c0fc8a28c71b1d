// `tlsmon query stable-areas --epoch N [--state S]`: the stable-area mask of one epoch
// (docs/schema.md, "stable_area_masks"): every supervoxel of the reference's segmentation —
// where it is, its normal, voxels and roughness — with its state in this epoch (stable: its
// change within its LoD95, in the datum unless inside a zone; unstable: beyond it; unknown: too
// few voxels of the epoch on it; not_planar: never in the datum) and its change along the
// normal with its LoD95 (mm).
#include <cmath>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"

namespace tlsmon {

namespace {

constexpr const char* kStates[] = {"stable", "unstable", "unknown", "not_planar"};

Cell millimetres(float metres) {
    return std::isnan(metres) ? Cell() : Cell(1e3 * metres);
}

}  // namespace

int run_query_stable_areas(const StableAreasQueryOptions& o) {
    return run_reporting_errors("query stable-areas", [&] {
        const auto db = open_for_reading(o.read);
        const auto epoch = db.epochs().find(o.epoch);
        if (!epoch)
            throw Error("no epoch " + std::to_string(o.epoch) + " in " + db.path().string());
        const auto mask = db.registrations().stable_areas_of_epoch(o.epoch);
        if (!mask) {
            throw Error("epoch " + std::to_string(o.epoch) + " (" +
                        std::string(to_string(epoch->status)) +
                        ") has no stable-area mask: the registration on stable areas did not run "
                        "for it (registration.method, docs/registration.md)");
        }
        if (o.read.format != OutputFormat::json) {
            std::cerr << "epoch " << o.epoch << ": " << mask->stable << " stable, "
                      << mask->unstable << " unstable of " << mask->states.size()
                      << " supervoxels (reference epoch " << mask->reference_epoch
                      << "); stable share " << std::lround(100 * mask->stable_share) << " %\n";
        }
        Table t{{"supervoxel", "state", "centroid_x_m", "centroid_y_m", "centroid_z_m", "normal_x",
                 "normal_y", "normal_z", "voxels", "roughness_mm", "change_mm", "lod95_mm"},
                {}};
        for (std::size_t k = 0; k < mask->states.size(); ++k) {
            const std::uint8_t s = mask->states[k];
            const char* state = s < 4 ? kStates[s] : "unknown";
            if (!o.state.empty() && o.state != state) continue;
            const auto& v = mask->supervoxels[k];
            t.rows.push_back({static_cast<std::int64_t>(k), state, v.centroid[0], v.centroid[1],
                              v.centroid[2], v.normal[0], v.normal[1], v.normal[2], v.voxels,
                              1e3 * v.roughness_m, millimetres(mask->changes[k]),
                              millimetres(mask->lods[k])});
        }
        print(std::cout, t, o.read.format);
    });
}

}  // namespace tlsmon
