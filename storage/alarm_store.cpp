// Alarm rules, alarm states and alarm events outside an epoch commit.
#include "storage/alarm_store.hpp"

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

AlarmRuleId AlarmStore::upsert_rule(const AlarmRule& rule) {
    return guarded(*c_, "upserting an alarm rule", [&] {
        SQLite::Statement s(c_->db,
                            "INSERT INTO alarm_rules (name, zone_id, quantity, definition, enabled)"
                            " VALUES (?,?,?,?,?) ON CONFLICT (name) DO UPDATE SET"
                            " zone_id = excluded.zone_id, quantity = excluded.quantity,"
                            " definition = excluded.definition, enabled = excluded.enabled"
                            " RETURNING id");
        s.bind(1, rule.name);
        s.bind(2, zone_id_by_name(*c_, rule.zone));
        s.bind(3, rule.quantity);
        s.bind(4, rule.definition_json);
        s.bind(5, rule.enabled ? 1 : 0);
        if (!s.executeStep()) throw_storage(*c_, "upserting rule '" + rule.name + "' gave no id");
        const AlarmRuleId id = s.getColumn(0).getInt64();
        while (s.executeStep()) {
        }
        return id;
    });
}

std::vector<AlarmRule> AlarmStore::rules() const {
    return guarded(*c_, "listing alarm rules", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT r.id, r.name, z.name, r.quantity, r.definition, r.enabled"
                            " FROM alarm_rules r JOIN zones z ON z.id = r.zone_id ORDER BY r.name");
        std::vector<AlarmRule> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getString(),
                           s.getColumn(4).getString(), s.getColumn(5).getInt() != 0});
        }
        return out;
    });
}

void AlarmStore::set_state(const AlarmState& state) {
    guarded(*c_, "writing an alarm state", [&] { write_alarm_state(*c_, state); });
}

std::vector<AlarmState> AlarmStore::states() const {
    return guarded(*c_, "listing alarm states", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT r.name, a.state, a.level, a.since, a.value, a.epoch_id"
                            " FROM alarm_states a JOIN alarm_rules r ON r.id = a.rule_id"
                            " ORDER BY r.name");
        std::vector<AlarmState> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getInt64(),
                           optional_double(s.getColumn(4)), optional_int64(s.getColumn(5))});
        }
        return out;
    });
}

void AlarmStore::record_event(const AlarmEvent& event) {
    guarded(*c_, "recording an alarm event", [&] { write_alarm_event(*c_, event); });
}

}  // namespace tlsmon
