#include "simulator/stable_ground.hpp"

#include <algorithm>
#include <string>

#include "simulator/terrain.hpp"

namespace tlsmon::sim {

std::vector<StableBox> stable_ground(const Site& site, const StableGroundLayout& layout) {
    std::vector<StableBox> out;
    const Pier& p = site.pier;
    const double m = layout.margin, g = layout.gap;
    for (const Block& b : site.terrain.blocks) {
        // From below the lowest ground around the box to just above the block's top.
        const double ground = std::min({terrain_height(site.terrain, b.lo.y() - m),
                                        terrain_height(site.terrain, b.hi.y() + m),
                                        terrain_height(site.terrain, 0.5 * (b.lo.y() + b.hi.y()))});
        const double z0 = std::min(ground, b.hi.z()) - 1.0;
        const double z1 = b.hi.z() + layout.headroom;
        const Eigen::Vector3d lo(b.lo.x() - m, b.lo.y() - m, z0);
        const Eigen::Vector3d hi(b.hi.x() + m, b.hi.y() + m, z1);
        const bool under_pier =
            b.lo.x() < p.x1 && b.hi.x() > p.x0 && b.lo.y() < p.y1 && b.hi.y() > p.y0;
        if (!under_pier) {
            out.push_back({b.name, lo, hi});
            continue;
        }
        // Around the pier's foot: the strips south, west, east and north of it.
        out.push_back({b.name + "-south", lo, {hi.x(), p.y0 - g, z1}});
        out.push_back({b.name + "-west", {lo.x(), p.y0 - g, z0}, {p.x0 - g, hi.y(), z1}});
        out.push_back({b.name + "-east", {p.x1 + g, p.y0 - g, z0}, {hi.x(), hi.y(), z1}});
        out.push_back({b.name + "-north", {p.x0 - g, p.y1 + g, z0}, {p.x1 + g, hi.y(), z1}});
    }
    if (!layout.valley_sides) return out;
    const Terrain& t = site.terrain;
    for (std::size_t k = 0; k + 1 < t.profile_y.size(); ++k) {
        const double y0 = t.profile_y[k], y1 = t.profile_y[k + 1];
        const double z0 = t.profile_z[k], z1 = t.profile_z[k + 1];
        if (z0 == z1) continue;  // the level floor: its part near the pier is above
        if (y0 < p.y1 + g && y1 > p.y0 - g) continue;  // the pier stands on this slope
        out.push_back({"valley-side-" + std::to_string(k + 1),
                       {p.x0 - layout.valley_width, y0, std::min(z0, z1) - 1.0},
                       {p.x1 + layout.valley_width, y1, std::max(z0, z1) + layout.headroom}});
    }
    return out;
}

}  // namespace tlsmon::sim
