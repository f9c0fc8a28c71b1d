// `tlsmon query keypoints [--zone Z]`: the keypoint stage's results per segment and epoch
// (docs/keypoints.md, "In the database"), read-only: one row per zone and epoch with the
// matches kept, the mean vector, its components along the wall and their LoD95. Zones
// without any keypoint row are left out.
#include <iostream>
#include <map>
#include <optional>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"
#include "pipeline/keypoint_results.hpp"

namespace tlsmon {

int run_query_keypoints(const KeypointsQueryOptions& options) {
    return run_reporting_errors("query keypoints", [&] {
        const auto range = time_range(options.read);
        const auto db = open_for_reading(options.read);
        // The figures with a value and, where stored, their LoD95.
        const std::vector<const char*> values{kKeypointDx,
                                              kKeypointDy,
                                              kKeypointDz,
                                              kKeypointAlongNormal,
                                              kKeypointAlongSurfaceH,
                                              kKeypointAlongSurfaceV};
        Table t{{"epoch", "acquired", "zone", "matches", "kept", "dx_m", "dy_m", "dz_m",
                 "along_normal_m", "along_surface_h_m", "along_surface_v_m", "lod95_h_m",
                 "lod95_v_m", "height_m"},
                {}};
        for (const auto& [zone, definition] : db.site().zones()) {
            if (!options.zone.empty() && zone != options.zone) continue;
            struct Row {
                UtcSeconds acquired = 0;
                std::map<std::string, SeriesPoint> points;
            };
            std::map<EpochId, Row> rows;
            const auto gather = [&](const char* quantity) {
                for (const auto& p : db.series().points(zone, quantity, range)) {
                    rows[p.epoch].acquired = p.acquired;
                    rows[p.epoch].points[quantity] = p;
                }
            };
            gather(kKeypointCount);
            for (const char* q : values) gather(q);
            gather(kKeypointHeight);
            for (const auto& [epoch, row] : rows) {
                const auto value = [&](const char* q) {
                    const auto it = row.points.find(q);
                    return it == row.points.end() ? std::optional<double>()
                                                  : std::optional<double>(it->second.value);
                };
                const auto lod = [&](const char* q) {
                    const auto it = row.points.find(q);
                    return it == row.points.end() ? std::optional<double>()
                                                  : it->second.uncertainty;
                };
                const auto count = row.points.find(kKeypointCount);
                const bool counted = count != row.points.end();
                std::vector<Cell> cells{epoch, format_utc(row.acquired), zone};
                cells.push_back(optional_cell(counted ? std::optional<std::int64_t>(count->second.n)
                                                      : std::nullopt));
                cells.push_back(
                    optional_cell(counted ? std::optional<std::int64_t>(
                                                static_cast<std::int64_t>(count->second.value))
                                          : std::nullopt));
                for (const char* q : values) cells.push_back(optional_cell(value(q)));
                cells.push_back(optional_cell(lod(kKeypointAlongSurfaceH)));
                cells.push_back(optional_cell(lod(kKeypointAlongSurfaceV)));
                cells.push_back(optional_cell(value(kKeypointHeight)));
                t.rows.push_back(std::move(cells));
            }
        }
        print(std::cout, t, options.read.format);
    });
}

}  // namespace tlsmon
