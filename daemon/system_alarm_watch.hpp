#pragma once
// The system alarms (alarms/system_alarms.hpp) of the running daemon: what it observes
// (newest epoch, the outcome of the last one processed, the database's disk, database
// errors) through the same state machine as the rules, stored as rules `system.*` of the
// zone "(system)". Events carry the wall-clock time of the observation.
#include <optional>

#include "alarms/system_alarms.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// The zone of the system rules (a rule names a zone); it holds no values.
inline constexpr const char* kSystemZone = "(system)";

// Stores the zone "(system)" and the five system rules (at start, after the configured
// zones and rules).
void store_system_alarm_rules(EpochDatabase& db);

// Feeds one observation to the system rules (fields absent keep their condition) in one
// immediate transaction. Returns the number of transitions written.
int observe_system_alarms(EpochDatabase& db, const SystemAlarmConfig& config,
                          const SystemObservation& seen);

// The newest acquisition time of any epoch in the database (done, rejected, failed or
// pending), for system.stale.
std::optional<UtcSeconds> newest_epoch_acquired(const EpochDatabase& db);

// Free share of the file system holding `path` (statvfs), nullopt when it cannot be read.
std::optional<double> disk_free_share(const std::filesystem::path& path);

}  // namespace tlsmon
