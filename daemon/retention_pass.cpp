#include "daemon/retention_pass.hpp"

#include <algorithm>
#include <span>

namespace tlsmon {

RetentionPassResult run_retention_pass(EpochDatabase& db, const RetentionPolicy& policy,
                                       const std::function<bool()>& stop) {
    auto& store = db.retention();
    RetentionPassResult r;
    r.size_before = store.size_bytes();
    r.plan = store.plan(policy);
    const std::span<const EpochId> thin(r.plan.thin);
    const auto batch = static_cast<std::size_t>(std::max(1, policy.batch_epochs));
    for (std::size_t at = 0; at < thin.size(); at += batch) {
        if (stop()) {
            r.stopped = true;
            break;
        }
        const auto done =
            store.thin(thin.subspan(at, std::min(batch, thin.size() - at)), now_utc());
        r.epochs_thinned += done.epochs;
        r.map_bytes_deleted += done.bytes;
    }
    if (!store.incremental_vacuum()) {
        // Only when there is something to give back: the VACUUM rewrites the whole file.
        if (store.free_pages() > 0 && !r.stopped) {
            try {
                store.enable_incremental_vacuum();
                r.converted = true;
                db.events().record({now_utc(), "info", "database_vacuumed",
                                    "the epoch database was rewritten (VACUUM) with incremental "
                                    "vacuum, so the retention policy's freed pages go back to the "
                                    "file system from now on",
                                    std::nullopt});
            } catch (const StorageError& e) {
                // A full disk: the freed pages stay in the file and are reused by new epochs,
                // so the file still stops growing; the next pass tries again.
                r.vacuum_error = e.what();
            }
        }
    } else {
        while (!stop()) {
            const auto released = store.release_free_pages(std::max(1, policy.vacuum_pages));
            r.pages_released += released;
            if (released == 0 || store.free_pages() == 0) break;
        }
        r.stopped = r.stopped || store.free_pages() > 0;
    }
    r.size_after = store.size_bytes();
    return r;
}

}  // namespace tlsmon
