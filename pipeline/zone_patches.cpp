#include "pipeline/zone_patches.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace tlsmon {

namespace {

// A patch belongs to a zone's face when its normal lies within 30° of the zone's design
// normal (a face's own patches lie within a few degrees of it).
const double kFaceCos = std::cos(30.0 * std::numbers::pi / 180.0);

}  // namespace

ZonePatches zone_patches(const StableAreaConfig& segmentation,
                         const ReferenceSupervoxels& supervoxels,
                         const std::vector<ZoneShape>& zones, double max_incidence_deg) {
    ZonePatches out;
    std::vector<std::vector<Eigen::Vector3d>> members(supervoxels.patches.size());
    for (std::size_t i = 0; i < supervoxels.samples.size(); ++i) {
        if (const auto l = supervoxels.label[i]; l >= 0)
            members[std::size_t(l)].push_back(supervoxels.samples[i]);
    }
    for (const auto& z : zones) out.zone_names.push_back(z.name);
    out.zone_patches.resize(zones.size());
    // A patch of plane as the registration on stable areas takes it — enough voxels, not a
    // line, not a sheet of rays from the scanner (mixed returns strung along the beams at an
    // edge: "planar" along the line of sight, their distance says nothing) — but without its
    // roughness limit: the stage's own, on the reference's points, decides.
    StableAreaConfig shape = segmentation;
    shape.max_roughness = std::numeric_limits<double>::infinity();
    const double max_incidence_cos = std::cos(max_incidence_deg * std::numbers::pi / 180);
    for (std::size_t k = 0; k < supervoxels.patches.size(); ++k) {
        const auto& sv = supervoxels.patches[k];
        if (!is_planar(shape, sv, supervoxels.viewpoint)) continue;
        const Eigen::Vector3d sight = (supervoxels.viewpoint - sv.centroid).normalized();
        if (std::abs(sv.normal.dot(sight)) < max_incidence_cos) continue;
        bool inside = false;
        const auto index = static_cast<std::uint32_t>(out.patches.size());
        for (std::size_t z = 0; z < zones.size(); ++z) {
            const ZoneShape& zone = zones[z];
            if (!zone.contains(sv.centroid)) continue;
            if (zone.normal.allFinite() &&
                std::abs(zone.normal.normalized().dot(sv.normal)) < kFaceCos)
                continue;
            out.zone_patches[z].push_back(index);
            inside = true;
        }
        if (!inside) continue;
        patches::Patch p;
        p.frame = patches::PatchFrame::about(sv.centroid, sv.normal);
        p.footprint = patches::footprint_of(p.frame, members[k], segmentation.voxel);
        out.patches.push_back(std::move(p));
        out.supervoxel.push_back(static_cast<std::uint32_t>(k));
    }
    return out;
}

}  // namespace tlsmon
