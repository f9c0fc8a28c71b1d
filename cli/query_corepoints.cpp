// `tlsmon query corepoints --epoch N [--out FILE]`: one epoch's M3C2 map, one row per core
// point: where it is and its normal (the m3c2 stage's reference product, stored in the
// reference cache), and what the epoch measured there (its float32 core point arrays).
#include <cmath>
#include <fstream>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "pipeline/m3c2_reference.hpp"

namespace tlsmon {

namespace {

// The m3c2 stage's reference product as the database holds it (whatever its parameters).
M3c2Reference stored_reference(const EpochDatabase& db) {
    for (const auto& e : db.reference_cache().entries()) {
        if (e.stage != M3c2Reference::kStage) continue;
        const CachedPayload cached = db.reference_cache().load(
            ReferenceCacheKey{e.stage, e.reference_sha256, e.params_hash, e.format_version});
        if (cached.status != CacheLookup::hit) {
            throw Error("the m3c2 reference product in " + db.path().string() +
                        " cannot be read: " + cached.reason);
        }
        return M3c2Reference::decode(cached.payload);
    }
    throw Error("no m3c2 reference product in " + db.path().string() +
                " (has the m3c2 stage run?)");
}

Cell value_cell(float v) {
    return std::isfinite(v) ? Cell(static_cast<double>(v)) : Cell();
}

}  // namespace

int run_query_corepoints(const CorePointsOptions& o) {
    return run_reporting_errors("query corepoints", [&] {
        const auto db = open_for_reading(o.read);
        const auto epoch = db.epochs().find(o.epoch);
        if (!epoch)
            throw Error("no epoch " + std::to_string(o.epoch) + " in " + db.path().string());
        const auto distance = db.series().core_point_array(o.epoch, "m3c2_distance_m");
        if (!distance) {
            throw Error("epoch " + std::to_string(o.epoch) + " (" +
                        std::string(to_string(epoch->status)) + ") has no M3C2 core points");
        }
        const auto array = [&](const char* quantity) {
            auto a = db.series().core_point_array(o.epoch, quantity);
            if (!a || a->values.size() != distance->values.size()) {
                throw Error("epoch " + std::to_string(o.epoch) + ": core point array '" + quantity +
                            "' is missing or of another length");
            }
            return a->values;
        };
        const auto lod = array("m3c2_lod95_m");
        const auto n1 = array("m3c2_n1");
        const auto n2 = array("m3c2_n2");
        const M3c2Reference ref = stored_reference(db);
        if (ref.reference.size() != distance->values.size()) {
            throw Error("epoch " + std::to_string(o.epoch) + " has " +
                        std::to_string(distance->values.size()) +
                        " core points, the stored m3c2 reference " +
                        std::to_string(ref.reference.size()) +
                        ": it was measured with other [m3c2] parameters or zones");
        }
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
            const float d = distance->values[k];
            // The reference's spread: beyond max_roughness, an edge and no distance.
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
