// Acknowledging through AlarmStore: the two ISA-18.2 acknowledge transitions only.
#include "daemon/alarm_actions.hpp"

#include "storage/epoch_database.hpp"

namespace tlsmon {

int acknowledge_alarm(EpochDatabase& db, const std::string& rule, AlarmActor actor,
                      UtcSeconds now) {
    const std::string who = actor == AlarmActor::scada ? "SCADA"
                            : actor == AlarmActor::cli ? "CLI"
                                                       : "rule";
    int changed = 0;
    for (AlarmState s : db.alarms().states()) {
        if (rule != "*" && s.rule != rule) continue;
        if (s.state != "unack" && s.state != "rtn_unack") continue;
        s.state = s.state == "unack" ? "ack" : "normal";
        if (s.state == "normal") s.level.clear();
        s.since = now;
        db.alarms().set_state(s);
        db.alarms().record_event(
            {now, s.rule, "ack", s.level, s.value, s.epoch, "acknowledged by " + who});
        ++changed;
    }
    return changed;
}

}  // namespace tlsmon
