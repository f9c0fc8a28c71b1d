#include "pipeline/core_point_map.hpp"

#include "core/error.hpp"
#include "core/utc_time.hpp"
#include "pipeline/stored_product.hpp"

namespace tlsmon {

CorePointMap read_core_point_map(const EpochDatabase& db, EpochId id) {
    const auto epoch = db.epochs().find(id);
    if (!epoch)
        throw NoCorePointMap("no epoch " + std::to_string(id) + " in " + db.path().string());
    const auto distance = db.series().core_point_array(id, "m3c2_distance_m");
    if (!distance) {
        if (const auto thinned = db.retention().maps_thinned_at(id)) {
            throw NoCorePointMap("epoch " + std::to_string(id) +
                                 ": its per-core-point maps were thinned by the retention policy "
                                 "on " +
                                 format_utc(*thinned) +
                                 " (docs/retention.md); its zone series is kept");
        }
        throw NoCorePointMap("epoch " + std::to_string(id) + " (" +
                             std::string(to_string(epoch->status)) + ") has no M3C2 core points");
    }
    const auto array = [&](const char* quantity) {
        auto a = db.series().core_point_array(id, quantity);
        if (!a || a->values.size() != distance->values.size()) {
            throw Error("epoch " + std::to_string(id) + ": core point array '" + quantity +
                        "' is missing or of another length");
        }
        return a->values;
    };
    CorePointMap m;
    m.distance = distance->values;
    m.lod95 = array("m3c2_lod95_m");
    m.n1 = array("m3c2_n1");
    m.n2 = array("m3c2_n2");
    m.reference = stored_product<M3c2Reference>(db);
    if (m.reference.reference.size() != m.distance.size()) {
        throw Error("epoch " + std::to_string(id) + " has " + std::to_string(m.distance.size()) +
                    " core points, the stored m3c2 reference " +
                    std::to_string(m.reference.reference.size()) +
                    ": it was measured with other [m3c2] parameters or zones");
    }
    return m;
}

}  // namespace tlsmon
