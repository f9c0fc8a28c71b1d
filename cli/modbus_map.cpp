// `tlsmon modbus-map --config FILE [--format markdown|csv]`: the register map the server
// shows for this configuration, for the SCADA integrator. Zones and rules take their slots
// from the database named by the configuration when it exists (read only), else from the
// configuration's order, as the daemon will number them at its first start.
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli/commands.hpp"
#include "config/config.hpp"
#include "daemon/modbus/modbus_snapshot.hpp"
#include "daemon/modbus/register_map.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

int run_modbus_map(const ModbusMapOptions& options) {
    try {
        const Config config = load_config(options.config);
        std::optional<EpochDatabase> db;
        if (std::filesystem::exists(config.paths.database)) {
            db = EpochDatabase::open(config.paths.database, EpochDatabase::Mode::read_only);
        }
        std::vector<std::string> zones;
        for (const auto& z : config.zones) zones.push_back(z.name);
        const MapInputs inputs = modbus_map_inputs(db ? &*db : nullptr, zones, config.modbus);
        const RegisterMap map = build_register_map(inputs);
        if (options.format == "csv") {
            std::cout << map_csv(map);
            return 0;
        }
        // What an integrator sets up before reading the table.
        const ModbusConfig& m = config.modbus;
        std::cout << "Modbus TCP server " << m.address << ":" << m.port << ", unit id " << m.unit_id
                  << (m.enabled ? "" : " (disabled: modbus.enabled = false)")
                  << ". Addresses from 0 (PDU addresses; `mbpoll -0`). 32-bit values (float32, "
                     "uint32) in two registers, word order "
                  << (m.word_order == WordOrder::abcd ? "ABCD (high word first)"
                                                      : "CDAB (low word first)")
                  << ", bytes big-endian within a register; 123456.0 reads "
                  << (m.word_order == WordOrder::abcd ? "0x47F1 0x2000" : "0x2000 0x47F1") << ". "
                  << (m.value_type == ModbusValueType::int32
                          ? "Zone values, LoD and rates as int32 in the unit of each row "
                            "(-2147483648: none)."
                          : "Zone values, LoD and rates as float32 (NaN: none).")
                  << "\n\n"
                  << map_markdown(map);
    } catch (const std::exception& e) {
        std::cerr << "tlsmon modbus-map: " << e.what() << '\n';
        return 1;
    }
    return 0;
}

}  // namespace tlsmon
