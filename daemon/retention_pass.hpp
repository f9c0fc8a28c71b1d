#pragma once
// One pass of the retention policy (docs/retention.md) over the epoch database: plan, thin
// the maps in batches of `batch_epochs` epochs (one transaction each, with its event), then
// give the freed pages back to the file system — `vacuum_pages` per transaction through the
// incremental vacuum, or, for a database made before incremental vacuum (schema < 18 files),
// once by a whole VACUUM that also converts it. The daemon's retention thread and
// `tlsmon retention run` both call it; `stop` is asked between transactions. It logs
// nothing: the caller reports the result.
#include <cstdint>
#include <functional>

#include "storage/epoch_database.hpp"

namespace tlsmon {

struct RetentionPassResult {
    RetentionPlan plan;
    std::int64_t epochs_thinned = 0;
    std::int64_t map_bytes_deleted = 0;
    std::int64_t size_before = 0;  // bytes (page_count x page_size)
    std::int64_t size_after = 0;
    std::int64_t pages_released = 0;
    bool converted = false;    // a whole VACUUM made the file incremental
    std::string vacuum_error;  // why the file was not shrunk ("" when it was or need not be)
    bool stopped = false;      // `stop` answered true before the pass was complete
};

RetentionPassResult run_retention_pass(
    EpochDatabase& db, const RetentionPolicy& policy,
    const std::function<bool()>& stop = [] { return false; });

}  // namespace tlsmon
