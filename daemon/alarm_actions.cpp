// Operator actions through the database: each one read-modify-write in one immediate
// transaction (AlarmStore::update), so it is safe while the daemon commits epochs: the
// busy timeout makes the one wait for the other.
#include "daemon/alarm_actions.hpp"

#include <functional>
#include <map>

#include "alarms/alarm_machine.hpp"
#include "core/error.hpp"
#include "daemon/alarm_shelving.hpp"
#include "pipeline/alarm_rows.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace {

AlarmActorKind kind_of(AlarmActor a) {
    switch (a) {
        case AlarmActor::rule:
            return AlarmActorKind::rule;
        case AlarmActor::scada:
            return AlarmActorKind::scada;
        case AlarmActor::cli:
            return AlarmActorKind::cli;
        case AlarmActor::web:
            return AlarmActorKind::web;
    }
    return AlarmActorKind::rule;
}

using Action = std::function<AlarmStep(const AlarmMachineState&)>;

// Applies `action` to the rule named (every rule when "*"); rules without a state row are
// normal. Returns how many changed.
int apply(EpochDatabase& db, const std::string& rule, const Action& action,
          const std::string& who = "", const std::string& comment = "") {
    std::map<std::string, bool> known;
    for (const auto& r : db.alarms().rules()) known[r.name] = true;
    if (rule != "*" && !known.count(rule)) {
        std::string names;
        for (const auto& [name, _] : known) names += (names.empty() ? "" : ", ") + name;
        throw Error("no alarm rule '" + rule + "' in " + db.path().string() +
                    " (rules: " + (names.empty() ? "none" : names) + ")");
    }
    int changed = 0;
    db.alarms().update([&](const std::vector<AlarmState>& states) {
        std::map<std::string, AlarmState> rows;
        for (const auto& s : states) rows.emplace(s.rule, s);
        AlarmRows out;
        changed = 0;
        for (const auto& [name, _] : known) {
            if (rule != "*" && name != rule) continue;
            const auto row = rows.find(name);
            AlarmRuleStatus status =
                row == rows.end() ? AlarmRuleStatus{} : rule_status(row->second);
            const AlarmStep step = action(status.machine);
            if (step.events.empty()) continue;
            status.machine = step.state;
            const auto value = row == rows.end() ? std::nullopt : row->second.value;
            const auto epoch = row == rows.end() ? std::nullopt : row->second.epoch;
            out.states.push_back(state_row(name, status, value, epoch));
            for (const auto& t : step.events) {
                out.events.push_back(event_row(name, t, value, epoch));
                if (!who.empty()) {  // the history names who, not only which side
                    out.events.back().actor += " " + who;
                    out.events.back().message += " (" + who + ")";
                }
                if (!comment.empty()) out.events.back().message += ": " + comment;
            }
            ++changed;
        }
        return out;
    });
    return changed;
}

}  // namespace

int acknowledge_alarm(EpochDatabase& db, const std::string& rule, AlarmActor actor, UtcSeconds now,
                      const std::string& who, const std::string& comment) {
    return apply(
        db, rule,
        [&](const AlarmMachineState& s) { return on_acknowledge(s, kind_of(actor), now); }, who,
        comment);
}

int shelve_alarm(EpochDatabase& db, const std::string& rule, UtcSeconds until, AlarmActor actor,
                 UtcSeconds now, const std::string& who, const std::string& comment) {
    return apply(
        db, rule,
        [&](const AlarmMachineState& s) { return on_shelve(s, until, kind_of(actor), now); }, who,
        comment);
}

int unshelve_alarm(EpochDatabase& db, const std::string& rule, AlarmActor actor, UtcSeconds now,
                   const std::string& who, const std::string& comment) {
    return apply(
        db, rule, [&](const AlarmMachineState& s) { return on_unshelve(s, kind_of(actor), now); },
        who, comment);
}

int expire_due_shelves(EpochDatabase& db, UtcSeconds now) {
    return apply(db, "*", [&](const AlarmMachineState& s) { return expire_shelve(s, now); });
}

int remove_alarm_from_service(EpochDatabase& db, const std::string& rule, AlarmActor actor,
                              UtcSeconds now, const std::string& who, const std::string& comment) {
    return apply(
        db, rule,
        [&](const AlarmMachineState& s) { return on_remove_from_service(s, kind_of(actor), now); },
        who, comment);
}

int return_alarm_to_service(EpochDatabase& db, const std::string& rule, AlarmActor actor,
                            UtcSeconds now, const std::string& who, const std::string& comment) {
    return apply(
        db, rule,
        [&](const AlarmMachineState& s) { return on_return_to_service(s, kind_of(actor), now); },
        who, comment);
}

}  // namespace tlsmon
