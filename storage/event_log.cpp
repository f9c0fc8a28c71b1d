#include "storage/event_log.hpp"

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

void EventLog::record(const SystemEvent& event) {
    guarded(*c_, "recording a system event", [&] { write_system_event(*c_, event); });
}

}  // namespace tlsmon
