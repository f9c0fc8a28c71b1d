#include "daemon/modbus/modbus_snapshot.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "alarms/alarm_rate.hpp"
#include "daemon/system_alarm_watch.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace {

constexpr UtcSeconds kDay = 86400;
constexpr UtcSeconds kValueLookBack = 30 * kDay;  // before the last epoch: older = none

}  // namespace

MapInputs modbus_map_inputs(const EpochDatabase* db, const std::vector<std::string>& config_zones,
                            const ModbusConfig& config) {
    MapInputs in;
    in.quantities = config.quantities;
    in.value_type = config.value_type;
    ZoneId next = 1;
    if (db) {
        for (const auto& [id, name] : db->site().zone_ids()) {
            if (name == kSystemZone) continue;  // the system alarms' zone holds no values
            in.zones.push_back({static_cast<int>(id - 1), name});
            next = std::max(next, id + 1);
        }
        for (const auto& rule : db->alarms().rules()) {
            in.rules.push_back({static_cast<int>(rule.id - 1), rule.name});
        }
    }
    for (const auto& name : config_zones) {
        const bool known = std::any_of(in.zones.begin(), in.zones.end(),
                                       [&](const MapSlot& z) { return z.name == name; });
        if (!known) in.zones.push_back({static_cast<int>(next++ - 1), name});
    }
    return in;
}

// The window of each zone quantity's `.rate`: that of the first enabled rate rule watching
// it (the rate its alarm evaluates), else a day.
double rate_window(const std::vector<AlarmRule>& rules, const std::string& zone,
                   const std::string& quantity) {
    for (const auto& rule : rules) {
        if (!rule.enabled || rule.zone != zone || rule.quantity != quantity) continue;
        const auto definition = nlohmann::json::parse(rule.definition_json, nullptr, false);
        if (definition.is_discarded()) continue;
        const auto window = definition.find("rate_window_seconds");
        if (window != definition.end() && window->is_number()) return window->get<double>();
    }
    return kDefaultRateWindowSeconds;
}

ModbusSnapshot read_modbus_snapshot(const EpochDatabase& db, const MapInputs& inputs,
                                    const ModbusConfig& config, UtcSeconds now) {
    ModbusSnapshot s;
    const StatusSummary summary = db.series().status_summary();
    s.database_ok = true;
    s.backlog = summary.backlog > 0;
    const auto count = [&](EpochStatus st) {
        const auto it = summary.epochs_by_status.find(st);
        return it == summary.epochs_by_status.end() ? std::int64_t{0} : it->second;
    };
    s.epochs_processed = static_cast<std::uint32_t>(
        count(EpochStatus::done) + count(EpochStatus::rejected) + count(EpochStatus::failed));
    if (summary.last_done) {
        s.last_epoch_time =
            static_cast<std::uint32_t>(std::max<UtcSeconds>(0, summary.last_done->acquired));
    }
    s.last_epoch_failed =
        summary.last_failure &&
        (!summary.last_done || summary.last_failure->updated >= summary.last_done->updated);
    s.stale = !summary.last_done ||
              static_cast<double>(now - summary.last_done->acquired) > config.stale_seconds;

    const auto rules = db.alarms().rules();
    for (const auto& z : inputs.zones) {
        for (std::size_t q = 0; q < inputs.quantities.size(); ++q) {
            TimeRange range;
            // Back from the last epoch, not from now: after an outage or in a replay the
            // latest values still show (flagged stale).
            range.from = (summary.last_done ? summary.last_done->acquired : now) - kValueLookBack;
            const auto points = db.series().points(z.name, inputs.quantities[q], range);
            if (points.empty()) continue;
            const SeriesPoint& last = points.back();
            ZoneValue v;
            v.zone_slot = z.slot;
            v.quantity_slot = static_cast<int>(q);
            v.value = last.value;
            v.lod = last.uncertainty;
            v.significant = last.significant;
            v.stale = static_cast<double>(now - last.acquired) > config.stale_seconds;
            std::vector<TimedValue> values;
            for (const auto& p : points) values.push_back({p.acquired, p.value});
            v.rate = rate_per_day(values, last.acquired,
                                  rate_window(rules, z.name, inputs.quantities[q]));
            if (const auto reg = db.registrations().of_epoch(last.epoch)) {
                v.unregistered = reg->method == kUnregistered;
                v.registration_degraded = !reg->accepted && !v.unregistered;
            }
            s.values.push_back(v);
        }
    }
    const auto states = db.alarms().states();
    for (const auto& rule : rules) {
        RuleStatus r;
        r.slot = static_cast<int>(rule.id - 1);
        r.name = rule.name;
        r.zone = rule.zone;
        r.quantity = rule.quantity;
        for (const auto& st : states) {
            if (st.rule == rule.name) {
                r.state = parse_isa_state(st.state);
                r.level = parse_alarm_level(st.level);
            }
        }
        s.rules.push_back(r);
    }
    return s;
}

}  // namespace tlsmon
