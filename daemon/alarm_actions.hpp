#pragma once
// Operator actions on alarms, shared by `tlsmon alarms` (CLI), the Modbus server (SCADA) and
// the dashboard (web): one path, three doors.
#include <string>

#include "core/utc_time.hpp"
namespace tlsmon {
class EpochDatabase;
enum class AlarmActor { rule, scada, cli, web };
// Acknowledges the alarm of rule `rule` (every rule's when rule == "*"): ISA-18.2
// unack -> ack, rtn_unack -> normal; other states unchanged. Writes the state and one event
// row per rule acknowledged, naming the actor ("SCADA", "CLI") and who it was (`who`: "modbus
// client 192.0.2.7:50122", "user alice"), in the event's actor and message, and the
// operator's `comment` at the message's end. Returns how many rules changed.
int acknowledge_alarm(EpochDatabase& db, const std::string& rule, AlarmActor actor, UtcSeconds now,
                      const std::string& who = "", const std::string& comment = "");
}  // namespace tlsmon
