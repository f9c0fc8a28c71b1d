#pragma once
// The alarm state machine of ANSI/ISA-18.2-2016 (IEC 62682:2014), fig. 5 "alarm state
// transition diagram": (state, input, time) -> (state, events). Pure: the caller supplies
// the time and persists the state.
//
//   A normal      process normal, acknowledged
//   B unack       process abnormal, unacknowledged          (annunciated, flashing)
//   C ack         process abnormal, acknowledged            (annunciated, steady)
//   D rtn_unack   process returned to normal, unacknowledged
//   shelved       suppressed by the operator until an expiry time
//   out_of_service  removed from service (maintenance); suppressed until returned
//
// Levels (warning < alert < alarm) ride on the states: a rise in level while annunciated is
// a new alarm (back to unack), a fall is recorded but keeps the acknowledgement. A latching
// rule stays in unack/ack when the process returns to normal, until acknowledged (ISA-18.2
// "latching alarm": the acknowledgement is the reset).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/utc_time.hpp"

namespace tlsmon {

enum class IsaState { normal, unack, ack, rtn_unack, shelved, out_of_service };
enum class AlarmLevel { none = 0, warning = 1, alert = 2, alarm = 3 };
enum class AlarmActorKind { rule, scada, cli, web };

// Storage names: "normal", "unack", "ack", "rtn_unack", "shelved", "out_of_service";
// levels "", "warning", "alert", "alarm"; actors "rule", "SCADA", "CLI", "web".
std::string_view to_string(IsaState s);
std::string_view to_string(AlarmLevel l);
std::string_view to_string(AlarmActorKind a);
// unack or rtn_unack: an annunciation no operator has acknowledged yet.
inline bool unacknowledged(IsaState s) {
    return s == IsaState::unack || s == IsaState::rtn_unack;
}
// Inverse of to_string; an unknown name is an Error naming it.
IsaState parse_isa_state(std::string_view name);
AlarmLevel parse_alarm_level(std::string_view name);

// What is stored per rule. `process` is the level of the process condition (after the
// rule's deadband and delays) as last reported, also while shelved or out of service, so
// that unshelving knows whether the alarm is still standing.
struct AlarmMachineState {
    IsaState state = IsaState::normal;
    AlarmLevel level = AlarmLevel::none;    // annunciated level ("" in normal)
    AlarmLevel process = AlarmLevel::none;  // current process condition
    UtcSeconds since = 0;                   // time of the last state change
    std::optional<UtcSeconds> shelved_until;
};

struct AlarmTransition {
    UtcSeconds time = 0;
    std::string kind;  // raise, escalate, deescalate, return, clear, ack, reset, shelve,
                       // unshelve, shelve_expired, out_of_service, in_service
    IsaState from = IsaState::normal;
    IsaState to = IsaState::normal;
    AlarmLevel level = AlarmLevel::none;
    AlarmActorKind actor = AlarmActorKind::rule;
};

struct AlarmStep {
    AlarmMachineState state;
    std::vector<AlarmTransition> events;  // in order; empty when nothing changed
};

// The process condition of the rule is now `level` (none = normal). First expires a shelve
// whose time has come (see expire_shelve).
AlarmStep on_process(const AlarmMachineState& s, AlarmLevel level, bool latching, UtcSeconds now);
// Operator acknowledgement: unack -> ack (or -> normal when latched and the process is
// normal), rtn_unack -> normal, ack of a latched alarm whose process is normal -> normal.
// Other states: no change, no event.
AlarmStep on_acknowledge(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now);
// A shelve is temporary (ISA-18.2 §11.8, "shelving"): at most this long. Longer is a
// removal from service, which the alarm list shows as such.
inline constexpr UtcSeconds kMaxShelveSeconds = 30 * 86400;
// Shelve until `until` (> now and at most kMaxShelveSeconds ahead, else an Error): from any
// state but out_of_service.
AlarmStep on_shelve(const AlarmMachineState& s, UtcSeconds until, AlarmActorKind actor,
                    UtcSeconds now);
// Unshelve / return to service: to unack when the process is abnormal (the alarm is
// annunciated afresh), else normal. No change when not shelved / not out of service.
AlarmStep on_unshelve(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now);
AlarmStep on_remove_from_service(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now);
AlarmStep on_return_to_service(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now);
// A shelve whose expiry is <= now ends as by unshelve, with event kind "shelve_expired" by
// the rule. Called by every other input first; the daemon also calls it on its own.
AlarmStep expire_shelve(const AlarmMachineState& s, UtcSeconds now);

}  // namespace tlsmon
