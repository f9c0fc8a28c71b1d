// Zones and alarm rules (from the configuration), alarm states and events, system events.
#include "storage/epoch_database.hpp"
#include "storage/epoch_database_impl.hpp"

namespace tlsmon {

ZoneId zone_id_by_name(EpochDatabase::Impl& impl, const std::string& zone) {
    SQLite::Statement s(impl.db, "SELECT id FROM zones WHERE name = ?");
    s.bind(1, zone);
    if (!s.executeStep()) throw_storage(impl, "no zone named '" + zone + "'");
    return s.getColumn(0).getInt64();
}

AlarmRuleId rule_id_by_name(EpochDatabase::Impl& impl, const std::string& rule) {
    SQLite::Statement s(impl.db, "SELECT id FROM alarm_rules WHERE name = ?");
    s.bind(1, rule);
    if (!s.executeStep()) throw_storage(impl, "no alarm rule named '" + rule + "'");
    return s.getColumn(0).getInt64();
}

void write_alarm_state(EpochDatabase::Impl& impl, const AlarmState& state) {
    SQLite::Statement s(impl.db,
                        "INSERT INTO alarm_states (rule_id, state, level, since, value, epoch_id)"
                        " VALUES (?,?,?,?,?,?) ON CONFLICT (rule_id) DO UPDATE SET"
                        " state = excluded.state, level = excluded.level,"
                        " since = excluded.since, value = excluded.value,"
                        " epoch_id = excluded.epoch_id");
    s.bind(1, rule_id_by_name(impl, state.rule));
    s.bind(2, state.state);
    s.bind(3, state.level);
    s.bind(4, static_cast<std::int64_t>(state.since));
    bind_optional(s, 5, state.value);
    bind_optional(s, 6, state.epoch);
    s.exec();
}

void write_alarm_event(EpochDatabase::Impl& impl, const AlarmEvent& event) {
    SQLite::Statement s(impl.db,
                        "INSERT INTO alarm_events (time, rule_id, kind, level, value, epoch_id,"
                        " message) VALUES (?,?,?,?,?,?,?)");
    s.bind(1, static_cast<std::int64_t>(event.time));
    s.bind(2, rule_id_by_name(impl, event.rule));
    s.bind(3, event.kind);
    s.bind(4, event.level);
    bind_optional(s, 5, event.value);
    bind_optional(s, 6, event.epoch);
    s.bind(7, event.message);
    s.exec();
}

void write_system_event(EpochDatabase::Impl& impl, const SystemEvent& event) {
    SQLite::Statement s(impl.db,
                        "INSERT INTO system_events (time, level, kind, message, epoch_id)"
                        " VALUES (?,?,?,?,?)");
    s.bind(1, static_cast<std::int64_t>(event.time));
    s.bind(2, event.level);
    s.bind(3, event.kind);
    s.bind(4, event.message);
    bind_optional(s, 5, event.epoch);
    s.exec();
}

ZoneId EpochDatabase::upsert_zone(const std::string& name, const std::string& definition_json) {
    return guarded(*impl_, "upserting a zone", [&] {
        SQLite::Statement s(impl_->db,
                            "INSERT INTO zones (name, definition) VALUES (?,?)"
                            " ON CONFLICT (name) DO UPDATE SET definition = excluded.definition"
                            " RETURNING id");
        s.bind(1, name);
        s.bind(2, definition_json);
        if (!s.executeStep()) throw_storage(*impl_, "upserting zone '" + name + "' gave no id");
        const ZoneId id = s.getColumn(0).getInt64();
        while (s.executeStep()) {
        }
        return id;
    });
}

std::vector<std::pair<std::string, std::string>> EpochDatabase::zones() const {
    return guarded(*impl_, "listing zones", [&] {
        SQLite::Statement s(impl_->db, "SELECT name, definition FROM zones ORDER BY name");
        std::vector<std::pair<std::string, std::string>> out;
        while (s.executeStep()) out.emplace_back(s.getColumn(0).getString(), s.getColumn(1));
        return out;
    });
}

AlarmRuleId EpochDatabase::upsert_alarm_rule(const AlarmRule& rule) {
    return guarded(*impl_, "upserting an alarm rule", [&] {
        SQLite::Statement s(impl_->db,
                            "INSERT INTO alarm_rules (name, zone_id, quantity, definition, enabled)"
                            " VALUES (?,?,?,?,?) ON CONFLICT (name) DO UPDATE SET"
                            " zone_id = excluded.zone_id, quantity = excluded.quantity,"
                            " definition = excluded.definition, enabled = excluded.enabled"
                            " RETURNING id");
        s.bind(1, rule.name);
        s.bind(2, zone_id_by_name(*impl_, rule.zone));
        s.bind(3, rule.quantity);
        s.bind(4, rule.definition_json);
        s.bind(5, rule.enabled ? 1 : 0);
        if (!s.executeStep())
            throw_storage(*impl_, "upserting rule '" + rule.name + "' gave no id");
        const AlarmRuleId id = s.getColumn(0).getInt64();
        while (s.executeStep()) {
        }
        return id;
    });
}

std::vector<AlarmRule> EpochDatabase::alarm_rules() const {
    return guarded(*impl_, "listing alarm rules", [&] {
        SQLite::Statement s(impl_->db,
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

void EpochDatabase::set_alarm_state(const AlarmState& state) {
    guarded(*impl_, "writing an alarm state", [&] { write_alarm_state(*impl_, state); });
}

std::vector<AlarmState> EpochDatabase::alarm_states() const {
    return guarded(*impl_, "listing alarm states", [&] {
        SQLite::Statement s(impl_->db,
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

void EpochDatabase::record_alarm_event(const AlarmEvent& event) {
    guarded(*impl_, "recording an alarm event", [&] { write_alarm_event(*impl_, event); });
}

void EpochDatabase::record_system_event(const SystemEvent& event) {
    guarded(*impl_, "recording a system event", [&] { write_system_event(*impl_, event); });
}

}  // namespace tlsmon
