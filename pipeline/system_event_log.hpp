#pragma once
#include <deque>
#include <optional>
#include <string>

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
    // The last write tried here failed for lack of space (StorageError::disk_full), or the
    // caller said so (`write_failed`); a later successful write clears it (`wrote`).
    bool disk_full() const { return disk_full_; }
    void write_failed(const StorageError& e) { disk_full_ = e.disk_full(); }
    void wrote() { disk_full_ = false; }

  private:
    static constexpr std::size_t capacity = 1000;
    std::deque<SystemEvent> waiting_;
    bool disk_full_ = false;
};

}  // namespace tlsmon
