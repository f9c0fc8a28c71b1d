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

#include "config/modbus_config.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

class EpochDatabase;

class ModbusService {
  public:
    // Acknowledges `rule` ("*" = all) on behalf of the SCADA client at `client` (address and
    // port); returns the rules changed.
    using Acknowledge = std::function<int(EpochDatabase&, const std::string& rule,
                                          const std::string& client, UtcSeconds now)>;

    // Starts listening at once (Error when it cannot).
    ModbusService(const ModbusConfig& config, const std::filesystem::path& database,
                  std::vector<std::string> config_zones, Acknowledge acknowledge);
    ~ModbusService();
    ModbusService(const ModbusService&) = delete;
    ModbusService& operator=(const ModbusService&) = delete;

    // An epoch was committed: rebuild the registers now.
    void epoch_committed();
    // The daemon's own view of the disk (kept here, in memory: with the disk full nothing
    // about it can be stored): the status bit and the system fault follow it.
    void set_disk_full(bool full);

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace tlsmon
