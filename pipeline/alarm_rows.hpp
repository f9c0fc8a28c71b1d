#pragma once
// The alarm state machine's values (alarms/) <-> the rows of AlarmStore (storage/).
#include <optional>
#include <string>

#include "alarms/rule_step.hpp"
#include "storage/alarm_store.hpp"

namespace tlsmon {

// A stored state; a rule without a row is normal with a fresh memory.
AlarmRuleStatus rule_status(const AlarmState& row);
AlarmState state_row(const std::string& rule, const AlarmRuleStatus& status,
                     std::optional<double> value, std::optional<EpochId> epoch);
// "unack -> ack by SCADA" in the message (no "by" for the rule); actor as stored
// ("rule", "SCADA", "CLI").
AlarmEvent event_row(const std::string& rule, const AlarmTransition& t, std::optional<double> value,
                     std::optional<EpochId> epoch);

}  // namespace tlsmon
