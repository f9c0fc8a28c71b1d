#pragma once
// An epoch database with a long series of epochs that carry per-core-point maps, for the
// retention tests: `days` x `per_day` epochs from `start` (UTC), each with one zone value and
// two float32 maps of `core_points` values; epoch 0 is the reference; the epochs named in
// `alarm_at` raise an alarm, those in `exclusion_at` exclude a target.
#include <SQLiteCpp/SQLiteCpp.h>

#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "storage/epoch_database.hpp"

namespace tlsmon::test {

inline constexpr UtcSeconds kSeriesStart = 1767225600;  // 2026-01-01T00:00:00Z, a Thursday

// One number `sql` reads from the file, through a connection of its own (read-write: the
// first reader after a killed writer recovers the WAL index).
inline std::int64_t sql_count(const std::filesystem::path& path, const std::string& sql) {
    SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE);
    return raw.execAndGet(sql).getInt64();
}

struct MapSeries {
    std::vector<EpochId> ids;  // in acquisition order
    std::vector<UtcSeconds> acquired;
};

inline MapSeries write_map_series(EpochDatabase& db, int days, int per_day, int core_points,
                                  UtcSeconds start, const std::set<int>& alarm_at = {},
                                  const std::set<int>& exclusion_at = {}) {
    db.site().upsert_zone("deck", "{}");
    db.alarms().upsert_rule({0, "deck high", "deck", "m3c2_median_m", "{}", true});
    MapSeries s;
    const int n = days * per_day;
    for (int i = 0; i < n; ++i) {
        char sha[65];
        std::snprintf(sha, sizeof sha, "%064x", i + 1);
        const UtcSeconds t = start + i * (86400 / per_day);
        const auto id = db.epochs().insert({sha, t, "/ingest/scan.ptx", 1000, std::nullopt}).id;
        db.epochs().claim(id);
        if (i == 0) db.epochs().set_reference(id);
        EpochResults r;
        r.zone_results.push_back({"deck", "m3c2_median_m", 1e-4 * i, 0.002, 100, false});
        std::vector<float> d(core_points), lod(core_points);
        for (int k = 0; k < core_points; ++k) {
            d[k] = static_cast<float>(1e-6 * (i + k));
            lod[k] = 0.002f;
        }
        r.core_point_arrays = {{"m3c2_distance_m", d}, {"m3c2_lod95_m", lod}};
        if (alarm_at.count(i)) {
            r.alarm_events.push_back({t, "deck high", "raise", "alarm", 0.02, id, "high", "rule"});
        }
        if (exclusion_at.count(i)) r.target_exclusions.push_back("T1");
        db.results().commit(id, r);
        s.ids.push_back(id);
        s.acquired.push_back(t);
    }
    return s;
}

}  // namespace tlsmon::test
