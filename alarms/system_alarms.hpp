#pragma once
// System alarms: conditions of tlsmon itself rather than of the structure. Each is a rule of
// its own (named below) running through the same state machine, with a fixed level.
#include <array>
#include <optional>
#include <string_view>

#include "alarms/alarm_machine.hpp"

namespace tlsmon {

enum class SystemAlarm {
    stale,
    registration_rejected,
    processing_failure,
    disk_nearly_full,
    database_error,
    central_forward
};
constexpr std::array<SystemAlarm, 6> kSystemAlarms{SystemAlarm::stale,
                                                   SystemAlarm::registration_rejected,
                                                   SystemAlarm::processing_failure,
                                                   SystemAlarm::disk_nearly_full,
                                                   SystemAlarm::database_error,
                                                   SystemAlarm::central_forward};
using SystemConditions = std::array<bool, kSystemAlarms.size()>;

// "system.stale", "system.registration_rejected", "system.processing_failure",
// "system.disk_nearly_full", "system.database_error", "system.central_forward".
std::string_view rule_name(SystemAlarm a);
// stale and database_error: alarm; processing_failure and disk_nearly_full: alert;
// registration_rejected and central_forward: warning (the site goes on alone; its results
// reach the central database once the fault is gone).
AlarmLevel system_alarm_level(SystemAlarm a);

struct SystemAlarmConfig {
    double cadence_seconds = 900;      // the scanner's interval
    double stale_factor = 3;           // stale when no new epoch for stale_factor x cadence
    double disk_free_min = 0.05;       // nearly full below this free fraction ...
    double disk_free_deadband = 0.01;  // ... and clear again above min + deadband
};

// What the daemon observed; absent fields leave their alarm's condition as it was.
struct SystemObservation {
    UtcSeconds now = 0;
    std::optional<UtcSeconds> last_epoch_acquired;  // newest epoch seen, any status
    std::optional<bool> last_epoch_rejected;        // the newest processed epoch
    std::optional<bool> last_epoch_failed;
    std::optional<double> disk_free_fraction;
    std::optional<bool> database_error;
    // Forwarding to the central database has failed for longer than [central] alarm_after.
    std::optional<bool> central_forward_failing;
};

// The process condition of each system alarm (in kSystemAlarms order), given the previous
// ones (for the disk deadband and the fields not observed).
SystemConditions system_conditions(const SystemAlarmConfig& config, const SystemObservation& seen,
                                   const SystemConditions& previous);

}  // namespace tlsmon
