// `tlsmon query stable-areas --epoch N [--state S]`: the stable-area mask of one epoch
// (docs/schema.md, "stable_area_masks"): every supervoxel of the reference's segmentation —
// where it is, its normal, voxels and roughness — with its state in this epoch (stable: its
// change within its LoD95, in the datum unless inside a zone; unstable: beyond it; unknown: too
// few voxels of the epoch on it; not_planar: never in the datum) and its change along the
// normal with its LoD95 (mm). With `--as-zones`, the unstable areas as `[[zone]]` tables
// instead (docs/registration.md, "Unstable areas").
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "algorithms/registration/unstable_areas.hpp"
#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "config/config.hpp"
#include "pipeline/stable_area_measurement.hpp"

namespace tlsmon {

namespace {

constexpr const char* kStates[] = {"stable", "unstable", "unknown", "not_planar"};

Cell millimetres(float metres) {
    return std::isnan(metres) ? Cell() : Cell(1e3 * metres);
}

// A normal is given to the zone (M3C2 then measures along it) only for an area that faces one
// way: a slope, a fill's face; not a parked vehicle or a heap.
constexpr double kMaxNormalSpreadDeg = 30;

std::string toml_vector(const Eigen::Vector3d& v, int decimals) {
    return fmt::format("[{:.{}f}, {:.{}f}, {:.{}f}]", v.x(), decimals, v.y(), decimals, v.z(),
                       decimals);
}

bool boxes_overlap(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper,
                   const ZoneConfig& z) {
    for (int i = 0; i < 3; ++i) {
        if (std::max(lower[i], z.min[i]) >= std::min(upper[i], z.max[i])) return false;
    }
    return true;
}

// The areas outside the configured zones whose supervoxels were unstable in this epoch and the
// `stable_persistent_epochs` − 1 before it, each as a [[zone]] table to add to the configuration,
// so that M3C2 measures it and alarm rules can watch it (a zone is never in the datum).
void print_as_zones(const StableAreasQueryOptions& o, const EpochDatabase& db, const Epoch& epoch,
                    const StableAreaMask& mask) {
    if (o.read.config.empty()) {
        throw Error(
            "--as-zones needs --config FILE: the zones already configured, the supervoxels' "
            "stable_seed and stable_persistent_epochs");
    }
    const Config config = load_config(o.read.config);
    const auto& sa = config.stable_areas;
    const auto before = db.registrations().recent_stable_area_states(
        epoch.acquired, mask.reference_epoch, mask.segmentation, sa.persistent_epochs);
    std::vector<ZoneShape> zones;
    for (const auto& z : config.zones) zones.push_back(zone_shape(z));
    std::vector<registration::AreaPatch> patches(mask.supervoxels.size());
    std::vector<std::uint32_t> outside;
    for (const auto k :
         registration::unstable_run(mask.states, before, sa.persistent_epochs,
                                    static_cast<std::uint8_t>(SupervoxelState::unstable), false)) {
        const auto& v = mask.supervoxels[k];
        patches[k] = {Eigen::Vector3d(v.centroid.data()), Eigen::Vector3d(v.normal.data()),
                      mask.changes[k], mask.lods[k]};
        const bool in_zone = std::any_of(zones.begin(), zones.end(), [&](const ZoneShape& z) {
            return z.contains(patches[k].centroid);
        });
        if (!in_zone) outside.push_back(k);
    }
    const auto areas = registration::unstable_areas(patches, outside, 2.0 * sa.seed);
    std::cerr << "epoch " << epoch.id << ": " << areas.size()
              << " unstable area(s) outside the zones, unstable in " << sa.persistent_epochs
              << " epochs in a row (registration.stable_persistent_epochs)\n";
    std::cout << fmt::format(
        "# The unstable areas of epoch {} outside the zones of\n#   {}\n# Added to it as "
        "zones, M3C2 measures them and alarm rules can watch them (a zone\n# is never in the "
        "datum); then tlsmon check-config.\n",
        epoch.id, o.read.config);
    // The supervoxels reach about half a seed beyond their centroids.
    const Eigen::Vector3d pad = Eigen::Vector3d::Constant(0.5 * sa.seed);
    for (std::size_t i = 0; i < areas.size(); ++i) {
        const auto& a = areas[i];
        const Eigen::Vector3d lower = a.lower - pad, upper = a.upper + pad;
        std::cout << fmt::format(
            "\n[[zone]]\nname = \"unstable area {}.{}\"\n"
            "# {} supervoxels about {} m, {:.1f} m across; change {:+.2f} to {:+.2f} mm "
            "(LoD95 up to {:.2f} mm)\nmin = {}\nmax = {}\n",
            epoch.id, i + 1, a.supervoxels.size(), toml_vector(a.centre, 1), 2.0 * a.extent,
            1e3 * a.min_change, 1e3 * a.max_change, 1e3 * a.max_lod, toml_vector(lower, 3),
            toml_vector(upper, 3));
        const double spread_deg = a.normal_spread_rad * 180.0 / std::numbers::pi;
        const auto overlapping = std::find_if(
            config.zones.begin(), config.zones.end(),
            [&](const ZoneConfig& z) { return z.normal && boxes_overlap(lower, upper, z); });
        if (spread_deg > kMaxNormalSpreadDeg) {
            std::cout << fmt::format(
                "# no normal: its supervoxels' normals lie up to {:.0f} deg from their mean\n",
                spread_deg);
        } else if (overlapping != config.zones.end()) {
            std::cout << fmt::format(
                "# no normal: the box overlaps zone \"{}\", whose normal would differ\n",
                overlapping->name);
        } else {
            std::cout << "normal = " << toml_vector(a.normal, 4) << "\n";
        }
    }
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
        if (o.as_zones) return print_as_zones(o, db, *epoch, *mask);
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
