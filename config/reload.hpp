#pragma once
// What a reload (SIGHUP) changes that must not pass unseen: zones, alarm rules, targets and
// stable regions it removes (each said in an event), a kind of them it removes entirely
// (refused: an empty or truncated file would silently end the monitoring; a restart
// applies such a file on purpose), and whether the Modbus or HTTP server must be restarted.
#include <string>
#include <vector>

#include "config/config.hpp"

namespace tlsmon {

struct ReloadChanges {
    std::string refused;               // why the fresh configuration is not applied; "" if it is
    std::vector<std::string> removed;  // "zone 'pier top'", "alarm rule 'r1'", ...
    bool modbus = false;               // a modbus.* value or the zones' list changed
    bool http = false;                 // an http.* value changed
    bool notify = false;               // a notify.* value, channel or route changed
};

ReloadChanges compare_for_reload(const Config& current, const Config& fresh);

}  // namespace tlsmon
