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
        // The block's bounds as it stands (a wall set at an angle: its corners' bounds).
        Eigen::AlignedBox3d box;
        const Eigen::Isometry3d pose = b.pose(0);
        const Eigen::AlignedBox3d own(b.lo - b.centre(), b.hi - b.centre());
        for (int c = 0; c < 8; ++c)
            box.extend(pose * own.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
        const Eigen::Vector3d blo = box.min(), bhi = box.max();
        // From below the lowest ground around the box to just above the block's top.
        const double ground = std::min({terrain_height(site.terrain, blo.y() - m),
                                        terrain_height(site.terrain, bhi.y() + m),
                                        terrain_height(site.terrain, 0.5 * (blo.y() + bhi.y()))});
        const double z0 = std::min(ground, bhi.z()) - 1.0;
        const double z1 = bhi.z() + layout.headroom;
        // A wall stands close to the pier: only a strip of ground at its foot with it.
        const double mb = b.kind == Block::Kind::wall ? layout.wall_margin : m;
        const Eigen::Vector3d lo(blo.x() - mb, blo.y() - mb, z0);
        const Eigen::Vector3d hi(bhi.x() + mb, bhi.y() + mb, z1);
        const bool under_pier =
            blo.x() < p.x1 && bhi.x() > p.x0 && blo.y() < p.y1 && bhi.y() > p.y0;
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
