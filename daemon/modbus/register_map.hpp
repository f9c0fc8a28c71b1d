#pragma once
// The Modbus register map, generated deterministically from the zones, the configured
// quantities and the alarm rules (docs/modbus.md). Addresses are 0-based protocol
// addresses. The map is versioned and stable: a zone's block and a rule's bits and coil sit
// at fixed strides indexed by the zone's / rule's slot, which is its database id - 1 (ids are
// given in order of first appearance and never reused: zones and rules are upserted by name
// and never deleted), and a quantity's slot is its position in `modbus.quantities` (append
// only). Adding a zone, rule or quantity therefore never moves an existing address.
#include <climits>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "alarms/alarm_machine.hpp"
#include "config/modbus_config.hpp"

namespace tlsmon {

inline constexpr int kModbusMapVersion = 1;

// Fixed input registers.
inline constexpr int kRegMapVersion = 0;
inline constexpr int kRegHeartbeat = 1;
inline constexpr int kRegStatus = 2;
inline constexpr int kRegLastEpochTime = 3;    // uint32, 2 registers
inline constexpr int kRegEpochsProcessed = 5;  // uint32, 2 registers
inline constexpr int kRegTestFloat = 7;        // float32, 2 registers
// Per zone and quantity: base + zone_slot * zone stride + quantity_slot * quantity stride.
inline constexpr int kRegZoneBase = 100;
inline constexpr int kRegZoneStride = 80;
inline constexpr int kRegQuantityStride = 10;
inline constexpr int kMaxQuantities = kRegZoneStride / kRegQuantityStride;
inline constexpr int kMaxZones = (65536 - kRegZoneBase) / kRegZoneStride;
// Offsets in a quantity block.
inline constexpr int kOffValue = 0, kOffLod = 2, kOffRate = 4, kOffQuality = 6, kOffLevel = 7,
                     kOffState = 8;

// Discrete inputs.
inline constexpr int kBitAnyAlarm = 0, kBitAnyUnacknowledged = 1, kBitSystemFault = 2;
inline constexpr int kBitRuleBase = 16;   // + rule_slot * 4 + level - 1 (warning 1 .. alarm 3)
inline constexpr int kBitRuleStride = 4;  // the 4th bit: the rule is unacknowledged
// Coils.
inline constexpr int kCoilAcknowledgeAll = 0;
inline constexpr int kCoilRuleBase = 16;  // + rule_slot
inline constexpr int kMaxRules = 65536 - kCoilRuleBase;

// Daemon status bits (input register kRegStatus).
inline constexpr std::uint16_t kStatusRunning = 1u << 0;
inline constexpr std::uint16_t kStatusDatabaseOk = 1u << 1;
inline constexpr std::uint16_t kStatusBacklog = 1u << 2;
inline constexpr std::uint16_t kStatusLastEpochFailed = 1u << 3;
inline constexpr std::uint16_t kStatusStale = 1u << 4;
inline constexpr std::uint16_t kStatusAnyAlarm = 1u << 5;
inline constexpr std::uint16_t kStatusDiskFull = 1u << 6;  // writes fail: nothing is stored

// Quality word bits of a zone value.
inline constexpr std::uint16_t kQualityValid = 1u << 0;
inline constexpr std::uint16_t kQualityStale = 1u << 1;
inline constexpr std::uint16_t kQualityBelowLod = 1u << 2;
inline constexpr std::uint16_t kQualityRegistrationDegraded = 1u << 3;
// The epoch was not registered (no targets, no ICP): its value mixes the scanner's own
// movement into the structure's, and alarm rules do not take it (docs/alarms.md).
inline constexpr std::uint16_t kQualityUnregistered = 1u << 4;

// ISA-18.2 state codes (register ".isa_state") and alarm level codes (".alarm_level").
// normal 0, unack 1, ack 2, rtn_unack 3, shelved 4, out_of_service 5 (IsaState's order).
std::uint16_t isa_state_code(IsaState state);
// none 0, warning 1, alert 2, alarm 3.
std::uint16_t alarm_level_code(AlarmLevel level);

struct MapSlot {
    int slot = 0;  // database id - 1
    std::string name;
};

struct MapInputs {
    std::vector<MapSlot> zones;
    std::vector<std::string> quantities;  // slot = index
    std::vector<MapSlot> rules;
    ModbusValueType value_type = ModbusValueType::float32;  // of value, LoD and rate
};

enum class ModbusTable { input_register, discrete_input, coil };
enum class ModbusType { uint16, uint32, int32, float32, bit };

// value_type int32: a quantity's fixed unit, from the unit its name ends with ("m": µm,
// "count": as it is, any other: thousandths), and the counts per stored unit.
struct Int32Scale {
    double counts_per_unit = 1e3;
    std::string unit;  // as the map prints it: "µm", "count", "1e-3 share"
};
Int32Scale int32_scale(const std::string& quantity);
// The register value of `value` in that scale: rounded to the nearest count; none, NaN or
// beyond ±2147483647: kInt32None.
inline constexpr std::int32_t kInt32None = INT32_MIN;
std::int32_t int32_value(const std::optional<double>& value, const Int32Scale& scale);

struct MapEntry {
    ModbusTable table = ModbusTable::input_register;
    int address = 0;  // 0-based protocol address
    int count = 1;    // registers (or bits)
    std::string name;
    ModbusType type = ModbusType::uint16;
    std::string unit;
    std::string meaning;
};

struct RegisterMap {
    std::vector<MapEntry> entries;  // by table, then address
    int input_registers = 0;        // one past the highest address used, per table
    int discrete_inputs = 0;
    int coils = 0;
};

// Throws Error when a slot is beyond the map's room (kMaxZones, kMaxRules, kMaxQuantities).
RegisterMap build_register_map(const MapInputs& inputs);

std::string map_markdown(const RegisterMap& map);
std::string map_csv(const RegisterMap& map);
const char* table_name(ModbusTable table);
const char* type_name(ModbusType type);

}  // namespace tlsmon
