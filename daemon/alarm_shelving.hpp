#pragma once
// Shelving (ISA-18.2: a temporary, operator-initiated suppression with an expiry), beside
// acknowledge_alarm (daemon/alarm_actions.hpp) and written the same way.
#include <string>

#include "core/utc_time.hpp"
#include "daemon/alarm_actions.hpp"

namespace tlsmon {

// Shelves the alarm of rule `rule` (every rule's when "*") until `until` (> now, else an
// Error): suppressed until then or until unshelved; at the expiry it is annunciated afresh
// if its condition still stands. An unknown rule is an Error naming the rules there are.
// Returns how many rules changed.
int shelve_alarm(EpochDatabase& db, const std::string& rule, UtcSeconds until, AlarmActor actor,
                 UtcSeconds now);
// Ends a shelve early. Returns how many rules changed (0 when none was shelved).
int unshelve_alarm(EpochDatabase& db, const std::string& rule, AlarmActor actor, UtcSeconds now);

}  // namespace tlsmon
