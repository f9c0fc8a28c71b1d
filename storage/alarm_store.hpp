#pragma once
// Alarm rules (from the configuration), the current state of each rule, and alarm events
// outside an epoch commit (acknowledge from SCADA, shelving). The state machine itself is
// alarms/; here are only its rows.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/event_log.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct AlarmRule {
    AlarmRuleId id = 0;
    std::string name;  // unique
    std::string zone;
    std::string quantity;
    std::string definition_json = "{}";  // levels, deadband, delays: owned by the alarm code
    bool enabled = true;
};

// Current state of one rule in the ISA-18.2 state machine (state names owned by the alarm
// code: "normal", "unack", "ack", "rtn_unack", "shelved", ...).
struct AlarmState {
    std::string rule;  // rule name
    std::string state;
    std::string level;  // "", "warning", "alert", "alarm"
    UtcSeconds since = 0;
    std::optional<double> value;
    std::optional<EpochId> epoch;
    std::string process;                      // level of the process condition ("" = normal)
    std::optional<UtcSeconds> shelved_until;  // state "shelved"
    std::string memory;                       // the rule's memory between epochs (alarms/)
    std::optional<UtcSeconds> evaluated;      // acquisition time of the last epoch evaluated
};

struct AlarmEvent {
    UtcSeconds time = 0;
    std::string rule;  // rule name
    std::string kind;  // "raise", "clear", "ack", "shelve", ...
    std::string level;
    std::optional<double> value;
    std::optional<EpochId> epoch;
    std::string message;
    std::string actor = "rule";  // "rule", "SCADA", "CLI"
};

// The clock an alarm event's time was read from: "acquisition" for a rule's own transitions
// (raise, clear, return to normal), stamped with the acquisition time of the epoch that
// caused them, so a backlog's alarms stand at the structure's time and not at the time it
// was processed; "system" for operators' actions and the system alarms ("system.*").
std::string_view alarm_event_time_base(std::string_view rule, std::string_view actor);

// The rows one alarm evaluation or operator action writes.
struct AlarmRows {
    std::vector<AlarmState> states;
    std::vector<AlarmEvent> events;
    std::vector<SystemEvent> system_events;  // what the rules did not take, and why
};

class AlarmStore {
  public:
    explicit AlarmStore(Connection& connection) : c_(&connection) {}

    // The rule's zone must exist (Site::upsert_zone).
    AlarmRuleId upsert_rule(const AlarmRule& rule);
    std::vector<AlarmRule> rules() const;
    void set_state(const AlarmState& state);
    std::vector<AlarmState> states() const;  // by rule name
    void record_event(const AlarmEvent& event);

    // Read-modify-write in ONE immediate transaction (safe beside the running daemon, which
    // waits for it through the busy timeout): `change` gets every rule's state and returns
    // the rows to write.
    void update(const std::function<AlarmRows(const std::vector<AlarmState>&)>& change);
    // Alarm events by time, newest last; `rule` filters when not empty.
    std::vector<AlarmEvent> events(const std::optional<UtcSeconds>& from,
                                   const std::string& rule = "") const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
