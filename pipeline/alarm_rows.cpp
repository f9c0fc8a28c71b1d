#include "pipeline/alarm_rows.hpp"

namespace tlsmon {

AlarmRuleStatus rule_status(const AlarmState& row) {
    AlarmRuleStatus s;
    s.machine.state = parse_isa_state(row.state);
    s.machine.level = parse_alarm_level(row.level);
    s.machine.process = parse_alarm_level(row.process);
    s.machine.since = row.since;
    s.machine.shelved_until = row.shelved_until;
    s.memory = rule_memory_from_text(row.memory);
    s.evaluated = row.evaluated;
    return s;
}

AlarmState state_row(const std::string& rule, const AlarmRuleStatus& s, std::optional<double> value,
                     std::optional<EpochId> epoch) {
    AlarmState row;
    row.rule = rule;
    row.state = std::string(to_string(s.machine.state));
    row.level = std::string(to_string(s.machine.level));
    row.since = s.machine.since;
    row.value = value;
    row.epoch = epoch;
    row.process = std::string(to_string(s.machine.process));
    row.shelved_until = s.machine.shelved_until;
    row.memory = to_text(s.memory);
    row.evaluated = s.evaluated;
    return row;
}

AlarmEvent event_row(const std::string& rule, const AlarmTransition& t, std::optional<double> value,
                     std::optional<EpochId> epoch) {
    AlarmEvent e;
    e.time = t.time;
    e.rule = rule;
    e.kind = t.kind;
    e.level = std::string(to_string(t.level));
    e.value = value;
    e.epoch = epoch;
    e.message = std::string(to_string(t.from)) + " -> " + std::string(to_string(t.to));
    if (t.actor != AlarmActorKind::rule) e.message += " by " + std::string(to_string(t.actor));
    e.actor = std::string(to_string(t.actor));
    return e;
}

}  // namespace tlsmon
