// Alarm rules, alarm states and alarm events outside an epoch commit.
#include "storage/alarm_store.hpp"

#include <cstdint>

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
                            "SELECT r.name, a.state, a.level, a.since, a.value, a.epoch_id,"
                            " a.process, a.shelved_until, a.memory, a.evaluated"
                            " FROM alarm_states a JOIN alarm_rules r ON r.id = a.rule_id"
                            " ORDER BY r.name");
        std::vector<AlarmState> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getInt64(),
                           optional_double(s.getColumn(4)), optional_int64(s.getColumn(5)),
                           s.getColumn(6).getString(), optional_int64(s.getColumn(7)),
                           s.getColumn(8).getString(), optional_int64(s.getColumn(9))});
        }
        return out;
    });
}

void AlarmStore::record_event(const AlarmEvent& event) {
    guarded(*c_, "recording an alarm event", [&] { write_alarm_event(*c_, event); });
}

void AlarmStore::update(const std::function<AlarmRows(const std::vector<AlarmState>&)>& change) {
    guarded(*c_, "updating alarm states", [&] {
        // IMMEDIATE: the write lock before the read, so no epoch commit slips in between.
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        const AlarmRows rows = change(states());
        for (const auto& a : rows.states) write_alarm_state(*c_, a);
        for (const auto& e : rows.events) write_alarm_event(*c_, e);
        tx.commit();
    });
}

std::string_view alarm_event_time_base(std::string_view rule, std::string_view actor) {
    return actor == "rule" && !rule.starts_with("system.") ? "acquisition" : "system";
}

std::vector<AlarmEvent> AlarmStore::events(const std::optional<UtcSeconds>& from,
                                           const std::string& rule) const {
    return guarded(*c_, "listing alarm events", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT a.time, r.name, a.kind, a.level, a.value, a.epoch_id,"
                            " a.message, a.actor FROM alarm_events a"
                            " JOIN alarm_rules r ON r.id = a.rule_id"
                            " WHERE a.time >= ? AND (? = '' OR r.name = ?) ORDER BY a.time, a.id");
        s.bind(1, static_cast<std::int64_t>(from.value_or(INT64_MIN)));
        s.bind(2, rule);
        s.bind(3, rule);
        std::vector<AlarmEvent> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getString(),
                           optional_double(s.getColumn(4)), optional_int64(s.getColumn(5)),
                           s.getColumn(6).getString(), s.getColumn(7).getString()});
        }
        return out;
    });
}

}  // namespace tlsmon
