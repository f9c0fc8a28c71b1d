// `tlsmon query corepoints --epoch N [--out FILE]`: one epoch's M3C2 map, one row per core
// point: where it is and its normal (the m3c2 stage's reference product, stored in the
// reference cache), and what the epoch measured there (its float32 core point arrays).
#include <cmath>
#include <fstream>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "pipeline/core_point_map.hpp"

namespace tlsmon {

namespace {

Cell value_cell(float v) {
    return std::isfinite(v) ? Cell(static_cast<double>(v)) : Cell();
}

}  // namespace

int run_query_corepoints(const CorePointsOptions& o) {
    return run_reporting_errors("query corepoints", [&] {
        const auto db = open_for_reading(o.read);
        const CorePointMap map = read_core_point_map(db, o.epoch);
        const M3c2Reference& ref = map.reference;
        const auto& distance = map.distance;
        const auto& lod = map.lod95;
        const auto& n1 = map.n1;
        const auto& n2 = map.n2;
        std::vector<std::string> zones(ref.reference.size());
        for (std::size_t z = 0; z < ref.zone_names.size(); ++z) {
            for (auto k : ref.zone_cores[z]) {
                zones[k] += (zones[k].empty() ? "" : ";") + ref.zone_names[z];
            }
        }
        Table t{{"core", "x", "y", "z", "nx", "ny", "nz", "normal_radius", "spread1", "distance",
                 "lod95", "n1", "n2", "significant", "zones"},
                {}};
        for (std::size_t k = 0; k < ref.reference.size(); ++k) {
            const auto& c = ref.reference.core_points()[k];
            const auto& n = ref.reference.normals()[k];
            const bool defined = n.allFinite();
            const float d = distance[k];
            // The reference's spread s1 of the LoD, its strays left out (max_roughness asks the
            // spread with them: beyond it, an edge and no distance).
            const double spread1 = ref.reference.reference_side[k].spread;
            t.rows.push_back(
                {static_cast<std::int64_t>(k), c.x(), c.y(), c.z(), defined ? Cell(n.x()) : Cell(),
                 defined ? Cell(n.y()) : Cell(), defined ? Cell(n.z()) : Cell(),
                 std::isfinite(ref.reference.normal_radius[k])
                     ? Cell(ref.reference.normal_radius[k])
                     : Cell(),
                 std::isfinite(spread1) ? Cell(spread1) : Cell(), value_cell(d), value_cell(lod[k]),
                 static_cast<std::int64_t>(n1[k]), static_cast<std::int64_t>(n2[k]),
                 std::isfinite(d) && std::abs(d) > lod[k], zones[k]});
        }
        if (o.out.empty()) {
            print(std::cout, t, o.read.format);
            return;
        }
        std::ofstream out(o.out);
        if (!out) throw Error("cannot write " + o.out);
        print(out, t, o.read.format == OutputFormat::json ? OutputFormat::json : OutputFormat::csv);
        out.close();
        if (!out) throw Error("cannot write " + o.out);
    });
}

}  // namespace tlsmon
