// `tlsmon modbus-map --config FILE [--format markdown|csv]`: the register map the server
// shows for this configuration, for the SCADA integrator. Zones and rules take their slots
// from the database named by the configuration when it exists (read only), else from the
// configuration's order, as the daemon will number them at its first start.
#include <filesystem>
#include <iostream>
#include <optional>

#include "daemon/commands.hpp"
#include "daemon/config.hpp"
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
        std::cout << (options.format == "csv" ? map_csv(map) : map_markdown(map));
    } catch (const std::exception& e) {
        std::cerr << "tlsmon modbus-map: " << e.what() << '\n';
        return 1;
    }
    return 0;
}

}  // namespace tlsmon
