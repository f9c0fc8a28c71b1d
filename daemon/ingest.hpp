#pragma once
// Turning a complete file in the ingest folder into an epoch row, once: the sha256 of its
// bytes is its identity, so the same scan seen twice, renamed or copied again is one epoch.
#include <filesystem>
#include <optional>
#include <string>

#include "config/config.hpp"
#include "pipeline/sha256.hpp"
#include "pipeline/system_event_log.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

enum class IngestOutcome {
    new_epoch,       // a pending epoch was inserted
    known,           // already an epoch (queued, or the file left in place in keep mode)
    duplicate,       // same content as an earlier epoch: removed or left, no new epoch
    quarantined,     // empty, or a copy of an epoch that failed: quarantined with the reason
    wait_for_epoch,  // a copy of an epoch not processed yet: ask again once it is
    unreadable,      // could not be read (permission): recorded as a failed epoch
    not_a_file,      // a symbolic link or other non-regular entry: never read, left in place
    retry_later,     // the database refused (disk full, locked): try again later
};

struct IngestContext {
    EpochDatabase& db;
    const Config& config;
    std::optional<StationId> station;
    SystemEventLog& events;
    // Receives the bytes of a file that became a new epoch, read and hashed once, so the
    // pipeline need not read them again (nullptr: not kept).
    HashedBytes* new_epoch_bytes = nullptr;
};

// The file moved to quarantine with its <name>.reason.txt (`tag` keeps names apart there) and
// an error event; left in place, and the event says why, when it cannot be moved.
IngestOutcome quarantine(IngestContext& ctx, const std::filesystem::path& file,
                         const std::string& tag, const std::string& reason,
                         std::optional<EpochId> epoch);

// An empty file, or a copy of a scan that could not be read, is never a duplicate to
// delete: it goes to quarantine with its reason. A copy of an epoch not yet processed
// waits (wait_for_epoch) until that epoch is done or failed. `epoch` receives the epoch the
// file was matched to, if any.
IngestOutcome ingest_file(IngestContext& ctx, const std::filesystem::path& file,
                          EpochId* epoch = nullptr);

}  // namespace tlsmon
