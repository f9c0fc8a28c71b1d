#pragma once
// What the Modbus server shows: a snapshot of the daemon's state (plain data read from the
// database after each epoch and on a timer) and the register image rendered from it by the
// register map. Pure code; the server thread only copies the image into libmodbus' mapping.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "alarms/alarm_machine.hpp"
#include "config/modbus_config.hpp"
#include "daemon/modbus/register_map.hpp"

namespace tlsmon {

// The latest value of one quantity in one zone.
struct ZoneValue {
    int zone_slot = 0;
    int quantity_slot = 0;
    std::optional<double> value;
    std::optional<double> lod;
    std::optional<double> rate;  // per day
    bool stale = false;
    bool significant = false;
    bool registration_degraded = false;
    bool unregistered = false;  // no registration took the epoch to the reference's frame
};

struct RuleStatus {
    int slot = 0;
    std::string name;
    std::string zone;
    std::string quantity;
    AlarmLevel level = AlarmLevel::none;
    IsaState state = IsaState::normal;
};

struct ModbusSnapshot {
    bool database_ok = false;
    bool backlog = false;
    bool last_epoch_failed = false;
    bool stale = false;
    bool disk_full = false;  // the daemon's own view (ModbusService::set_disk_full)
    std::uint32_t last_epoch_time = 0;
    std::uint32_t epochs_processed = 0;
    std::vector<ZoneValue> values;
    std::vector<RuleStatus> rules;
};

struct RegisterImage {
    std::vector<std::uint16_t> input_registers;  // the heartbeat is the server's to set
    std::vector<std::uint8_t> discrete_inputs;
    // Coil address -> the rule it acknowledges ("*" for acknowledge-all, "" unused).
    std::vector<std::string> coil_rules;
};

// Every zone value of `inputs` starts as NaN with quality 0; the snapshot fills in what it has.
RegisterImage render_registers(const RegisterMap& map, const MapInputs& inputs,
                               const ModbusSnapshot& snapshot, WordOrder order);

}  // namespace tlsmon
