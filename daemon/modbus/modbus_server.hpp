#pragma once
// The Modbus TCP server: ONE thread owns the libmodbus context and mapping. It frames
// requests itself (MBAP header, non-blocking sockets, a select() loop with a timeout), so a
// client that sends half a frame, random bytes or nothing never blocks the others; libmodbus
// builds the answers (modbus_reply) from the mapping. The register image comes from
// publish(); the heartbeat register is the server's own (+1 per second of its clock).
#include <functional>
#include <memory>
#include <string>

#include "config/modbus_config.hpp"
#include "daemon/modbus/register_image.hpp"

namespace tlsmon {

class ModbusServer {
  public:
    // Called on the server thread for each acknowledge coil written to 1 ("*" = all), with
    // the client's address and port ("192.0.2.7:50122"); it must only hand the request on
    // (the acknowledgement itself writes the database).
    using AcknowledgeRequest =
        std::function<void(const std::string& rule, const std::string& client)>;

    // Listens on config.address:port at once; Error naming the address when it cannot.
    ModbusServer(const ModbusConfig& config, AcknowledgeRequest acknowledge);
    ~ModbusServer();  // stops the thread, closes every connection
    ModbusServer(const ModbusServer&) = delete;
    ModbusServer& operator=(const ModbusServer&) = delete;

    // The registers to show from now on (taken by the server thread at its next turn).
    void publish(std::shared_ptr<const RegisterImage> image);

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace tlsmon
