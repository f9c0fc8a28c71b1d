#pragma once
// Turning a complete file in the ingest folder into an epoch row, once: the sha256 of its
// bytes is its identity, so the same scan seen twice, renamed or copied again is one epoch.
#include <deque>
#include <filesystem>
#include <optional>
#include <string>

#include "daemon/config.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// System events are logged at once and written to the database when it accepts them: while
// the disk is full they wait in memory (at most `capacity`, oldest dropped) and are written
// by the next flush().
class SystemEventLog {
  public:
    void record(EpochDatabase& db, const std::string& level, const std::string& kind,
                const std::string& message, std::optional<EpochId> epoch = std::nullopt);
    void flush(EpochDatabase& db);
    std::size_t waiting() const { return waiting_.size(); }

  private:
    static constexpr std::size_t capacity = 1000;
    std::deque<SystemEvent> waiting_;
};

enum class IngestOutcome {
    new_epoch,    // a pending epoch was inserted
    known,        // already an epoch (queued, or the file left in place in keep mode)
    duplicate,    // same content as an earlier epoch: removed or archived, no new epoch
    unreadable,   // could not be read (permission): recorded as a failed epoch
    retry_later,  // the database refused (disk full, locked): try again later
};

struct IngestContext {
    EpochDatabase& db;
    const Config& config;
    std::optional<StationId> station;
    SystemEventLog& events;
};

IngestOutcome ingest_file(IngestContext& ctx, const std::filesystem::path& file);

}  // namespace tlsmon
