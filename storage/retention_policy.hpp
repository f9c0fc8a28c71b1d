#pragma once
// The retention policy of the per-core-point maps (docs/retention.md): every epoch's zone
// series is kept for ever (a few kB); its per-core-point arrays (M3C2 distances, LoD95, ...;
// tens of kB to MB per epoch) are thinned by age: all of them while young, then the first
// epoch of each UTC day, then the first of each ISO week. Protected epochs (the reference,
// epochs with alarm events or alarm state, targets excluded, pinned by an operator) are never
// thinned. Age is measured from the newest epoch's acquisition time, not the wall clock: a
// backlog ingested late or a wrong system clock never thins what the series has not passed.
#include <cstdint>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct RetentionPolicy {
    bool enabled = true;
    double keep_all_days = 30;     // every epoch's maps while younger than this
    double keep_daily_days = 365;  // then the day's first until this age; then the week's first
    int batch_epochs = 50;         // epochs thinned per transaction (ingest waits at most one)
    int vacuum_pages = 2048;       // free pages returned to the file system per transaction
    double interval = 3600;        // seconds between the daemon's passes
    bool operator==(const RetentionPolicy&) const = default;
};

// An epoch that still has per-core-point maps (or, for the archive, its scan).
struct MapEpoch {
    EpochId id = 0;
    UtcSeconds acquired = 0;
    bool is_protected = false;
};

// Which maps a pass keeps and thins, and why.
struct RetentionPlan {
    UtcSeconds now = 0;               // the newest epoch's acquisition time
    std::vector<EpochId> thin;        // newest first (see plan_by_age)
    std::int64_t kept_young = 0;      // younger than keep_all_days
    std::int64_t kept_daily = 0;      // the first of their UTC day
    std::int64_t kept_weekly = 0;     // the first of their ISO week
    std::int64_t kept_protected = 0;  // protected and not counted above
};

// The tiers by age for `epochs` (any order) at `now`: every epoch younger than
// `keep_all_days`, then the first of each UTC day until `keep_daily_days`, then the first of
// each ISO week, and the protected ones; the rest is thinned, newest first. Pure. The day's
// (week's) first epoch is taken among the epochs given (those that still have what is
// thinned), so the epoch kept for a day is also the one kept for its week later: a pass never
// needs what an earlier pass thinned. Thinned newest first, a pass stopped after any prefix of
// `thin` leaves a series whose plan is the rest of `thin`. The maps' policy and the archive's
// (storage/archive_policy.hpp) share it.
RetentionPlan plan_by_age(std::vector<MapEpoch> epochs, UtcSeconds now, double keep_all_days,
                          double keep_daily_days);

// The plan for the maps of `epochs`.
RetentionPlan plan_retention(std::vector<MapEpoch> epochs, UtcSeconds now,
                             const RetentionPolicy& policy);

}  // namespace tlsmon
