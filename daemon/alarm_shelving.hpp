#pragma once
// Suppression by an operator (ISA-18.2): shelving, temporary with an expiry, and removal
// from service for maintenance, beside acknowledge_alarm (daemon/alarm_actions.hpp) and
// written the same way.
#include <string>

#include "core/utc_time.hpp"
#include "daemon/alarm_actions.hpp"

namespace tlsmon {

// Shelves the alarm of rule `rule` (every rule's when "*") until `until` (> now, else an
// Error): suppressed until then or until unshelved; at the expiry it is annunciated afresh
// if its condition still stands. An unknown rule is an Error naming the rules there are.
// Returns how many rules changed.
int shelve_alarm(EpochDatabase& db, const std::string& rule, UtcSeconds until, AlarmActor actor,
                 UtcSeconds now, const std::string& who = "", const std::string& comment = "");
// Ends a shelve early. Returns how many rules changed (0 when none was shelved).
int unshelve_alarm(EpochDatabase& db, const std::string& rule, AlarmActor actor, UtcSeconds now,
                   const std::string& who = "", const std::string& comment = "");
// Ends every shelve whose expiry is <= now (event `shelve_expired`, by the rule): the
// daemon calls it every `daemon.status_interval`, so an expiry does not wait for the rule's
// next epoch. Returns how many rules changed.
int expire_due_shelves(EpochDatabase& db, UtcSeconds now);

// Removes the rule from service (maintenance of the scanner, works on the structure): it
// keeps following its condition without annunciating it until returned to service, with no
// expiry. Returns how many rules changed (0 when already out of service).
int remove_alarm_from_service(EpochDatabase& db, const std::string& rule, AlarmActor actor,
                              UtcSeconds now, const std::string& who = "",
                              const std::string& comment = "");
// Returns it to service: annunciated afresh (unack) if its condition stands, else normal.
int return_alarm_to_service(EpochDatabase& db, const std::string& rule, AlarmActor actor,
                            UtcSeconds now, const std::string& who = "",
                            const std::string& comment = "");

}  // namespace tlsmon
