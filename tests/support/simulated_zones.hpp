#pragma once
// The zones a site engineer would draw on a simulated pier, as `tlsmon simulate` writes them
// into site.toml (demo/site_config_writer.cpp): the two visible faces whole, edges and
// corners included, with their design normals — the west face's box starting 0.5 m behind
// the corner, so that the two meet without overlapping — and 10 m bands of the south face.
// Shared by the M3C2 pipeline tests and the M3C2 stage bench.
#include <vector>

#include "algorithms/zones/zone_shape.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::test {

inline std::vector<ZoneShape> simulated_pier_zones(const sim::Site& site) {
    const auto& p = site.pier;
    ZoneShape south = box_zone("south", {p.x0, p.y0 - 0.5, 0.0}, {p.x1, p.y0 + 0.5, p.height});
    south.normal = {0, -1, 0};
    std::vector<ZoneShape> zones{south};
    for (auto& b : bands_of(south, 2, 10.0, 0.0, p.height)) zones.push_back(b);
    ZoneShape west = box_zone("west", {p.x0 - 0.5, p.y0 + 0.5, 0.0}, {p.x0 + 0.5, p.y1, p.height});
    west.normal = {-1, 0, 0};
    zones.push_back(west);
    return zones;
}

}  // namespace tlsmon::test
