#include "alarms/system_alarms.hpp"

namespace tlsmon {

std::string_view rule_name(SystemAlarm a) {
    switch (a) {
        case SystemAlarm::stale:
            return "system.stale";
        case SystemAlarm::registration_rejected:
            return "system.registration_rejected";
        case SystemAlarm::processing_failure:
            return "system.processing_failure";
        case SystemAlarm::disk_nearly_full:
            return "system.disk_nearly_full";
        case SystemAlarm::database_error:
            return "system.database_error";
        case SystemAlarm::central_forward:
            return "system.central_forward";
    }
    return "system.unknown";
}

AlarmLevel system_alarm_level(SystemAlarm a) {
    switch (a) {
        case SystemAlarm::stale:
        case SystemAlarm::database_error:
            return AlarmLevel::alarm;
        case SystemAlarm::processing_failure:
        case SystemAlarm::disk_nearly_full:
            return AlarmLevel::alert;
        case SystemAlarm::registration_rejected:
        case SystemAlarm::central_forward:
            return AlarmLevel::warning;
    }
    return AlarmLevel::alarm;
}

SystemConditions system_conditions(const SystemAlarmConfig& c, const SystemObservation& seen,
                                   const SystemConditions& previous) {
    SystemConditions out = previous;
    if (seen.last_epoch_acquired) {
        out[0] = static_cast<double>(seen.now - *seen.last_epoch_acquired) >
                 c.stale_factor * c.cadence_seconds;
    }
    if (seen.last_epoch_rejected) out[1] = *seen.last_epoch_rejected;
    if (seen.last_epoch_failed) out[2] = *seen.last_epoch_failed;
    if (seen.disk_free_fraction) {
        const double limit = previous[3] ? c.disk_free_min + c.disk_free_deadband : c.disk_free_min;
        out[3] = *seen.disk_free_fraction < limit;
    }
    if (seen.database_error) out[4] = *seen.database_error;
    if (seen.central_forward_failing) out[5] = *seen.central_forward_failing;
    return out;
}

}  // namespace tlsmon
