#pragma once
// The system's event log in the database (start, stop, disk full, reload, quarantine, ...),
// beside the log file: `tlsmon events` lists it together with the alarm events.
#include <optional>
#include <string>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct SystemEvent {
    UtcSeconds time = 0;
    std::string level;  // "debug", "info", "warning", "error"
    std::string kind;   // "start", "stop", "disk_full", "config_reload", "quarantine", ...
    std::string message;
    std::optional<EpochId> epoch;
};

class EventLog {
  public:
    explicit EventLog(Connection& connection) : c_(&connection) {}

    void record(const SystemEvent& event);

  private:
    Connection* c_;
};

}  // namespace tlsmon
