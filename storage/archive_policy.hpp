#pragma once
// The archive policy of the raw scans (docs/retention.md, "The archive of scans"): the scan
// files in `paths.archive` are thinned by age with the tiers of the maps' policy (every scan
// while young, then the first of each UTC day, then the first of each ISO week;
// storage/retention_policy.hpp), but the scans of protected epochs (the reference, epochs
// with alarm events or standing alarm state, targets excluded, pinned) are never removed.
// Optionally the kept scans, once past the young tier, are re-encoded as E57 (bit-packed
// scaled integers: a third to a quarter of an ASCII export), except those the state names:
// the reference's scan is read again and checked against its sha256, so it stays byte for
// byte. Off by default: deleting raw data is the site's decision.
#include <cstdint>
#include <string>
#include <vector>

#include "storage/retention_policy.hpp"

namespace tlsmon {

enum class ScanReencoding { none, e57 };

struct ArchivePolicy {
    bool enabled = false;
    double keep_all_days = 7;     // every scan while younger than this
    double keep_daily_days = 90;  // then the day's first until this age; then the week's first
    ScanReencoding reencode = ScanReencoding::none;
    double e57_resolution = 1e-5;  // m per count of the re-encoded coordinates
    int batch_scans = 50;          // scans removed per transaction
    bool operator==(const ArchivePolicy&) const = default;
};

// A scan file of an epoch in the archive.
struct ArchivedScan {
    EpochId id = 0;
    UtcSeconds acquired = 0;
    std::string path;             // where it is now
    std::string sha256;           // the epoch's: the ingested file's content
    std::int64_t bytes = 0;       // its size as recorded (the ingested file, or the re-encoded one)
    bool is_protected = false;    // never removed (the maps' protection)
    bool named_by_state = false;  // the reference and the like: never re-encoded either
    bool reencode_failed = false;  // tried once: not tried again
};

struct ArchivePlan {
    RetentionPlan tiers;                 // tiers.thin: the ids of `remove`
    std::vector<ArchivedScan> remove;    // newest first, as tiers.thin
    std::vector<ArchivedScan> reencode;  // kept, past the young tier, not E57 yet; newest first
    std::int64_t scans = 0;              // in the archive now
    std::int64_t bytes = 0;              // their size
    std::int64_t bytes_to_free = 0;      // the size of `remove`
};

// Pure: the plan for `scans` (any order) at `now` (the newest epoch's acquisition time).
ArchivePlan plan_archive(std::vector<ArchivedScan> scans, UtcSeconds now,
                         const ArchivePolicy& policy);

// Whether `path` names an E57 file (by its extension, any case).
bool is_e57_path(const std::string& path);

}  // namespace tlsmon
