// Row reads and single-row writes shared by the stores (see shared_rows.hpp).
#include "storage/shared_rows.hpp"

#include <cstdio>

#include "storage/connection.hpp"

namespace tlsmon {

const char* const kEpochColumns =
    "id, sha256, acquired, discovered, updated, file_path, file_size, station_id, status, "
    "reason, point_count, read_ms, register_ms, analyse_ms, total_ms, archive_path";

Epoch read_epoch(SQLite::Statement& s) {
    Epoch e;
    e.id = s.getColumn(0).getInt64();
    e.sha256 = s.getColumn(1).getString();
    e.acquired = s.getColumn(2).getInt64();
    e.discovered = s.getColumn(3).getInt64();
    e.updated = s.getColumn(4).getInt64();
    e.file_path = s.getColumn(5).getString();
    e.file_size = s.getColumn(6).getInt64();
    e.station = optional_int64(s.getColumn(7));
    e.status = epoch_status_from_string(s.getColumn(8).getString());
    e.reason = s.getColumn(9).getString();
    e.point_count = optional_int64(s.getColumn(10));
    e.timings.read_ms = optional_double(s.getColumn(11));
    e.timings.register_ms = optional_double(s.getColumn(12));
    e.timings.analyse_ms = optional_double(s.getColumn(13));
    e.timings.total_ms = optional_double(s.getColumn(14));
    e.archive_path = optional_string(s.getColumn(15));
    return e;
}

ZoneId zone_id_by_name(Connection& c, const std::string& zone) {
    SQLite::Statement s(c.db, "SELECT id FROM zones WHERE name = ?");
    s.bind(1, zone);
    if (!s.executeStep()) throw_storage(c, "no zone named '" + zone + "'");
    return s.getColumn(0).getInt64();
}

// The id of a quantity name, inserted on first use (inside the caller's transaction).
std::int64_t quantity_id(Connection& c, const std::string& name) {
    if (name.empty()) throw_storage(c, "a zone result needs a quantity name");
    SQLite::Statement insert(
        c.db, "INSERT INTO quantities (name) VALUES (?) ON CONFLICT (name) DO NOTHING");
    insert.bind(1, name);
    insert.exec();
    SQLite::Statement s(c.db, "SELECT id FROM quantities WHERE name = ?");
    s.bind(1, name);
    if (!s.executeStep()) throw_storage(c, "quantity '" + name + "' vanished");
    return s.getColumn(0).getInt64();
}

AlarmRuleId rule_id_by_name(Connection& c, const std::string& rule) {
    SQLite::Statement s(c.db, "SELECT id FROM alarm_rules WHERE name = ?");
    s.bind(1, rule);
    if (!s.executeStep()) throw_storage(c, "no alarm rule named '" + rule + "'");
    return s.getColumn(0).getInt64();
}

void write_alarm_state(Connection& c, const AlarmState& state) {
    SQLite::Statement s(c.db,
                        "INSERT INTO alarm_states (rule_id, state, level, since, value, epoch_id,"
                        " process, shelved_until, memory, evaluated)"
                        " VALUES (?,?,?,?,?,?,?,?,?,?) ON CONFLICT (rule_id) DO UPDATE SET"
                        " state = excluded.state, level = excluded.level,"
                        " since = excluded.since, value = excluded.value,"
                        " epoch_id = excluded.epoch_id, process = excluded.process,"
                        " shelved_until = excluded.shelved_until, memory = excluded.memory,"
                        " evaluated = excluded.evaluated");
    s.bind(1, rule_id_by_name(c, state.rule));
    s.bind(2, state.state);
    s.bind(3, state.level);
    s.bind(4, static_cast<std::int64_t>(state.since));
    bind_optional(s, 5, state.value);
    bind_optional(s, 6, state.epoch);
    s.bind(7, state.process);
    bind_optional(s, 8, state.shelved_until);
    s.bind(9, state.memory);
    bind_optional(s, 10, state.evaluated);
    s.exec();
}

void write_alarm_event(Connection& c, const AlarmEvent& event) {
    SQLite::Statement s(c.db,
                        "INSERT INTO alarm_events (time, rule_id, kind, level, value, epoch_id,"
                        " message, actor) VALUES (?,?,?,?,?,?,?,?)");
    s.bind(1, static_cast<std::int64_t>(event.time));
    s.bind(2, rule_id_by_name(c, event.rule));
    s.bind(3, event.kind);
    s.bind(4, event.level);
    bind_optional(s, 5, event.value);
    bind_optional(s, 6, event.epoch);
    s.bind(7, event.message);
    s.bind(8, event.actor);
    s.exec();
}

void write_system_event(Connection& c, const SystemEvent& event) {
    SQLite::Statement s(c.db,
                        "INSERT INTO system_events (time, level, kind, message, epoch_id)"
                        " VALUES (?,?,?,?,?)");
    s.bind(1, static_cast<std::int64_t>(event.time));
    s.bind(2, event.level);
    s.bind(3, event.kind);
    s.bind(4, event.message);
    bind_optional(s, 5, event.epoch);
    s.exec();
}

std::string format_mib(std::int64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
    return text;
}

}  // namespace tlsmon
