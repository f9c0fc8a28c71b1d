#pragma once
// Alarm rules (from the configuration), the current state of each rule, and alarm events
// outside an epoch commit (acknowledge from SCADA, shelving). The state machine itself is
// alarms/; here are only its rows.
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
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
    std::string level;  // "", "H", "HH", ...
    UtcSeconds since = 0;
    std::optional<double> value;
    std::optional<EpochId> epoch;
};

struct AlarmEvent {
    UtcSeconds time = 0;
    std::string rule;  // rule name
    std::string kind;  // "raise", "clear", "ack", "shelve", ...
    std::string level;
    std::optional<double> value;
    std::optional<EpochId> epoch;
    std::string message;
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

  private:
    Connection* c_;
};

}  // namespace tlsmon
