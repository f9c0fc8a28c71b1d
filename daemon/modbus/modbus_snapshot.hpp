#pragma once
// The register map's inputs and the snapshot, read from the epoch database.
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "daemon/modbus/register_image.hpp"
#include "storage/alarm_store.hpp"

namespace tlsmon {

class EpochDatabase;

// Zones and rules with their slots: the database's (id - 1), then the configured zones the
// database does not know yet, with the ids the daemon will give them at start (next ids, in
// configuration order). `db` may be null (no database yet): the configuration's order alone.
MapInputs modbus_map_inputs(const EpochDatabase* db, const std::vector<std::string>& config_zones,
                            const ModbusConfig& config);

ModbusSnapshot read_modbus_snapshot(const EpochDatabase& db, const MapInputs& inputs,
                                    const ModbusConfig& config, UtcSeconds now);

// The window of a zone quantity's `.rate` registers: the first enabled rate rule's on it
// (alarms/alarm_rate.hpp), else a day.
double rate_window(const std::vector<AlarmRule>& rules, const std::string& zone,
                   const std::string& quantity);

}  // namespace tlsmon
