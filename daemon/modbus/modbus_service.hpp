#pragma once
// The daemon's Modbus side: the server thread (modbus_server.hpp) and a snapshot thread
// with its own database connection, which rebuilds the register image after each epoch
// commit and every `modbus.snapshot_interval`, and carries out SCADA's acknowledgements.
// Neither thread waits for the pipeline, so the heartbeat runs on while an epoch is processed.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "daemon/modbus/modbus_config.hpp"

namespace tlsmon {

class EpochDatabase;

class ModbusService {
  public:
    // Acknowledges `rule` ("*" = all) on behalf of SCADA; returns the rules changed.
    using Acknowledge = std::function<int(EpochDatabase&, const std::string& rule, UtcSeconds now)>;

    // Starts listening at once (Error when it cannot).
    ModbusService(const ModbusConfig& config, const std::filesystem::path& database,
                  std::vector<std::string> config_zones, Acknowledge acknowledge);
    ~ModbusService();
    ModbusService(const ModbusService&) = delete;
    ModbusService& operator=(const ModbusService&) = delete;

    // An epoch was committed: rebuild the registers now.
    void epoch_committed();

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace tlsmon
