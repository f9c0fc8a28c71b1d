#pragma once
// Epochs whose scans lie in an archive folder, for the archive policy's tests: small
// structured scans written as PTX (each epoch its own content), committed as processed
// epochs with their archive_path, the first one the reference.
#include <cmath>
#include <filesystem>
#include <set>
#include <vector>

#include "formats/ptx_writer.hpp"
#include "pipeline/sha256.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon::test {

// A 30 x 40 grid scan with empty cells and intensity; `i` moves it.
inline Scan archive_grid_scan(int i) {
    Scan s;
    s.pose = Eigen::Translation3d(2.0, -1.0, 0.5) *
             Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.1, 0.2, 1.0).normalized());
    s.grid = ScanGrid{30, 40, {}, {}};
    for (std::uint32_t c = 0; c < 40; ++c)
        for (std::uint32_t r = 0; r < 30; ++r) {
            if ((r + c) % 5 == 0) continue;  // no return
            const double az = 0.02 * c, el = -0.3 + 0.02 * r, range = 8.0 + 1e-4 * i + 0.01 * r;
            s.xyz.push_back(s.pose * Eigen::Vector3d(range * std::cos(el) * std::cos(az),
                                                     range * std::cos(el) * std::sin(az),
                                                     range * std::sin(el)));
            s.intensity.push_back(static_cast<float>((r * 13 + c * 7 + i) % 1000) / 1000.0f);
            s.grid->row.push_back(r);
            s.grid->column.push_back(c);
        }
    return s;
}

// The zone and alarm rule the epochs' rows name.
inline void prepare_archive_site(EpochDatabase& db) {
    db.site().upsert_zone("deck", "{}");
    db.alarms().upsert_rule({0, "deck high", "deck", "m3c2_median_m", "{}", true});
}

// An epoch acquired at `t`, processed, its scan `file` (already in the archive); with an
// alarm event when `alarm`.
inline EpochId add_archived_epoch(EpochDatabase& db, UtcSeconds t,
                                  const std::filesystem::path& file, bool alarm = false) {
    const auto id =
        db.epochs()
            .insert({sha256_file(file), t, "/ingest" / file.filename(),
                     static_cast<std::int64_t>(std::filesystem::file_size(file)), std::nullopt})
            .id;
    db.epochs().claim(id);
    if (!db.epochs().reference()) db.epochs().set_reference(id);
    EpochResults r;
    r.zone_results.push_back({"deck", "m3c2_median_m", 1e-4, 0.002, 100, false});
    r.archive_path = file.string();
    if (alarm)
        r.alarm_events.push_back({t, "deck high", "raise", "alarm", 0.02, id, "high", "rule"});
    db.results().commit(id, r);
    return id;
}

// `count` epochs, `per_day` a day from `start`, with their PTX files `scan_<i>.ptx` in
// `archive`; alarms at the indices in `alarm_at`. The epochs' ids in order.
inline std::vector<EpochId> write_archive_series(EpochDatabase& db,
                                                 const std::filesystem::path& archive, int count,
                                                 int per_day, UtcSeconds start,
                                                 const std::set<int>& alarm_at = {}) {
    prepare_archive_site(db);
    std::vector<EpochId> ids;
    for (int i = 0; i < count; ++i) {
        const auto file = archive / ("scan_" + std::to_string(i) + ".ptx");
        write_ptx(archive_grid_scan(i), file);
        ids.push_back(
            add_archived_epoch(db, start + i * (86400 / per_day), file, alarm_at.count(i) > 0));
    }
    return ids;
}

}  // namespace tlsmon::test
