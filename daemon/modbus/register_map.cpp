#include "daemon/modbus/register_map.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>

#include "core/csv.hpp"
#include "core/error.hpp"

namespace tlsmon {

namespace {

// "m3c2_median_m" -> "m": the unit is the suffix after the last underscore, by the naming of
// the quantities (docs/storage.md); "" when the name has none.
std::string unit_of(const std::string& quantity) {
    const auto u = quantity.rfind('_');
    return u == std::string::npos ? "" : quantity.substr(u + 1);
}

}  // namespace

Int32Scale int32_scale(const std::string& quantity) {
    const std::string unit = unit_of(quantity);
    if (unit == "m") return {1e6, "µm"};
    if (unit == "count") return {1.0, "count"};
    return {1e3, "1e-3 " + unit};
}

std::int32_t int32_value(const std::optional<double>& value, const Int32Scale& scale) {
    if (!value || !std::isfinite(*value)) return kInt32None;
    const double counts = std::round(*value * scale.counts_per_unit);
    if (!(std::abs(counts) <= double(INT32_MAX))) return kInt32None;
    return static_cast<std::int32_t>(counts);
}

std::uint16_t isa_state_code(IsaState state) {
    return static_cast<std::uint16_t>(state);
}

std::uint16_t alarm_level_code(AlarmLevel level) {
    return static_cast<std::uint16_t>(level);
}

const char* table_name(ModbusTable table) {
    switch (table) {
        case ModbusTable::input_register:
            return "input register";
        case ModbusTable::discrete_input:
            return "discrete input";
        case ModbusTable::coil:
            return "coil";
    }
    return "?";
}

const char* type_name(ModbusType type) {
    switch (type) {
        case ModbusType::uint16:
            return "uint16";
        case ModbusType::int32:
            return "int32";
        case ModbusType::uint32:
            return "uint32";
        case ModbusType::float32:
            return "float32";
        case ModbusType::bit:
            return "bit";
    }
    return "?";
}

RegisterMap build_register_map(const MapInputs& in) {
    using T = ModbusTable;
    using Y = ModbusType;
    RegisterMap m;
    auto add = [&m](T table, int address, int count, std::string name, Y type, std::string unit,
                    std::string meaning) {
        m.entries.push_back(
            {table, address, count, std::move(name), type, std::move(unit), std::move(meaning)});
    };
    add(T::input_register, kRegMapVersion, 1, "map_version", Y::uint16, "",
        "Version of this register layout (" + std::to_string(kModbusMapVersion) + ")");
    add(T::input_register, kRegHeartbeat, 1, "heartbeat", Y::uint16, "s",
        "+1 every second while the server runs (wraps at 65535)");
    add(T::input_register, kRegStatus, 1, "daemon_status", Y::uint16, "bits",
        "bit 0 running, 1 database readable, 2 epochs waiting, 3 last epoch failed or "
        "rejected, 4 no epoch for modbus.stale_seconds, 5 any alarm active");
    add(T::input_register, kRegLastEpochTime, 2, "last_epoch_time", Y::uint32, "s",
        "Acquisition time of the last epoch processed, UTC seconds since 1970 (0: none)");
    add(T::input_register, kRegEpochsProcessed, 2, "epochs_processed", Y::uint32, "",
        "Epochs processed (done, rejected or failed) in the database");
    add(T::input_register, kRegTestFloat, 2, "test_float", Y::float32, "",
        "Always 123456.0: checks the client's float and word order");

    if (in.quantities.size() > static_cast<std::size_t>(kMaxQuantities)) {
        throw Error("the Modbus map has room for " + std::to_string(kMaxQuantities) +
                    " quantities per zone, not " + std::to_string(in.quantities.size()));
    }
    std::vector<MapSlot> zones = in.zones;
    std::sort(zones.begin(), zones.end(),
              [](const MapSlot& a, const MapSlot& b) { return a.slot < b.slot; });
    for (const auto& z : zones) {
        if (z.slot < 0 || z.slot >= kMaxZones) {
            throw Error("zone '" + z.name + "' (slot " + std::to_string(z.slot) +
                        ") lies beyond the Modbus map's " + std::to_string(kMaxZones) + " zones");
        }
        for (std::size_t q = 0; q < in.quantities.size(); ++q) {
            const int base =
                kRegZoneBase + z.slot * kRegZoneStride + static_cast<int>(q) * kRegQuantityStride;
            const std::string& qn = in.quantities[q];
            const std::string id = z.name + "/" + qn;
            const bool integer = in.value_type == ModbusValueType::int32;
            const std::string unit = integer ? int32_scale(qn).unit : unit_of(qn);
            const Y type = integer ? Y::int32 : Y::float32;
            const std::string none = integer ? "-2147483648" : "NaN";
            add(T::input_register, base + kOffValue, 2, id + ".value", type, unit,
                "Latest value of " + qn + " in zone " + z.name + " (" + none + ": none)");
            add(T::input_register, base + kOffLod, 2, id + ".lod", type, unit,
                "Its level of detection / uncertainty (" + none + ": none)");
            add(T::input_register, base + kOffRate, 2, id + ".rate", type,
                unit.empty() ? "1/d" : unit + "/d",
                "Rate of change: least-squares slope over the 24 h up to the latest value "
                "(NaN: fewer than 2 values)");
            add(T::input_register, base + kOffQuality, 1, id + ".quality", Y::uint16, "bits",
                "bit 0 valid, 1 stale, 2 below LoD (not significant), 3 registration degraded");
            add(T::input_register, base + kOffLevel, 1, id + ".alarm_level", Y::uint16, "",
                "Highest level of the rules on it: 0 none, 1 warning, 2 alert, 3 alarm");
            add(T::input_register, base + kOffState, 1, id + ".isa_state", Y::uint16, "",
                "ISA-18.2 state of the rule with that level: 0 normal, 1 unacknowledged, "
                "2 acknowledged, 3 returned unacknowledged, 4 shelved, 5 out of service");
        }
    }

    add(T::discrete_input, kBitAnyAlarm, 1, "any_alarm", Y::bit, "",
        "Some rule is at a level (warning or above)");
    add(T::discrete_input, kBitAnyUnacknowledged, 1, "any_unacknowledged", Y::bit, "",
        "Some rule is unacknowledged or returned unacknowledged");
    add(T::discrete_input, kBitSystemFault, 1, "system_fault", Y::bit, "",
        "Database unreadable, or the last epoch failed or was rejected");
    add(T::coil, kCoilAcknowledgeAll, 1, "acknowledge_all", Y::bit, "",
        "Write 1: acknowledge every rule (reads back 0)");
    std::vector<MapSlot> rules = in.rules;
    std::sort(rules.begin(), rules.end(),
              [](const MapSlot& a, const MapSlot& b) { return a.slot < b.slot; });
    for (const auto& r : rules) {
        if (r.slot < 0 || r.slot >= kMaxRules ||
            kBitRuleBase + (r.slot + 1) * kBitRuleStride > 65536) {
            throw Error("alarm rule '" + r.name + "' lies beyond the Modbus map's room");
        }
        const int bit = kBitRuleBase + r.slot * kBitRuleStride;
        for (int level = 1; level <= 3; ++level) {
            const std::string name(to_string(static_cast<AlarmLevel>(level)));
            add(T::discrete_input, bit + level - 1, 1, r.name + "." + name, Y::bit, "",
                "Rule " + r.name + " is at level " + name + " or above");
        }
        add(T::discrete_input, bit + 3, 1, r.name + ".unacknowledged", Y::bit, "",
            "Rule " + r.name + " waits for acknowledgement");
        add(T::coil, kCoilRuleBase + r.slot, 1, r.name + ".acknowledge", Y::bit, "",
            "Write 1: acknowledge rule " + r.name + " (reads back 0)");
    }
    std::stable_sort(m.entries.begin(), m.entries.end(), [](const MapEntry& a, const MapEntry& b) {
        if (a.table != b.table) return a.table < b.table;
        return a.address < b.address;
    });
    for (const auto& e : m.entries) {
        int& size = e.table == T::input_register   ? m.input_registers
                    : e.table == T::discrete_input ? m.discrete_inputs
                                                   : m.coils;
        size = std::max(size, e.address + e.count);
    }
    return m;
}

std::string map_markdown(const RegisterMap& map) {
    std::string out =
        "| table | address | count | name | type | unit | meaning |\n"
        "|---|---|---|---|---|---|---|\n";
    for (const auto& e : map.entries) {
        out += std::string("| ") + table_name(e.table) + " | " + std::to_string(e.address) + " | " +
               std::to_string(e.count) + " | `" + e.name + "` | " + type_name(e.type) + " | " +
               e.unit + " | " + e.meaning + " |\n";
    }
    return out;
}

std::string map_csv(const RegisterMap& map) {
    std::string out = "table,address,count,name,type,unit,meaning\n";
    for (const auto& e : map.entries) {
        append_csv_line(out,
                        std::vector<std::string>{table_name(e.table), std::to_string(e.address),
                                                 std::to_string(e.count), e.name, type_name(e.type),
                                                 e.unit, e.meaning});
    }
    return out;
}

}  // namespace tlsmon
