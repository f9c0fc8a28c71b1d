#pragma once
// The retention of per-core-point maps in the epoch database (docs/retention.md): operators'
// pins, the plan of a pass (storage/retention_policy.hpp) and its two writing steps, each in
// short transactions so the ingest never waits long: thinning a batch of epochs' maps (with
// a system event naming them), and returning the freed pages to the file system (SQLite's
// incremental vacuum). A pass killed at any moment leaves every batch thinned or untouched
// and the file consistent.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"
#include "storage/retention_policy.hpp"

namespace tlsmon {

struct EpochPin {
    EpochId epoch = 0;
    UtcSeconds acquired = 0;
    UtcSeconds pinned_at = 0;
    std::string pinned_by;
    std::string note;
    bool has_maps = false;  // false: its maps were thinned before it was pinned (or never made)
};

struct ThinnedBatch {
    std::int64_t epochs = 0;  // epochs whose maps were deleted
    std::int64_t bytes = 0;   // bytes of map data deleted
};

class RetentionStore {
  public:
    explicit RetentionStore(Connection& connection) : c_(&connection) {}

    // Pins `epoch` (StorageError when there is no such epoch); false when it was pinned
    // already. With a system event naming `by`, in one transaction.
    bool pin(EpochId epoch, const std::string& by, const std::string& note, UtcSeconds at);
    // false when it was not pinned.
    bool unpin(EpochId epoch, const std::string& by, UtcSeconds at);
    std::vector<EpochPin> pins() const;
    // Whether `epoch` has any per-core-point map.
    bool has_maps(EpochId epoch) const;
    // When the retention policy deleted `epoch`'s maps; nullopt when it did not.
    std::optional<UtcSeconds> maps_thinned_at(EpochId epoch) const;

    // The epochs with maps, which of them are protected, and the newest acquisition time.
    RetentionPlan plan(const RetentionPolicy& policy) const;
    // Deletes the maps of `epochs` (in plan order), except those protected by now (an operator
    // may have pinned one since the plan), in one immediate transaction with a system event.
    ThinnedBatch thin(std::span<const EpochId> epochs, UtcSeconds at);

    // SQLite's auto_vacuum mode is `incremental` (new databases are created so).
    bool incremental_vacuum() const;
    // Converts the file to incremental auto_vacuum by a VACUUM: rewrites it whole, holding
    // the write lock meanwhile (seconds for hundreds of MB), once per database.
    void enable_incremental_vacuum();
    std::int64_t free_pages() const;
    // page_count x page_size: the database's size once the WAL is checkpointed.
    std::int64_t size_bytes() const;
    // Returns up to `pages` free pages to the file system in one transaction; the pages
    // returned.
    std::int64_t release_free_pages(int pages);

  private:
    Connection* c_;
};

}  // namespace tlsmon
