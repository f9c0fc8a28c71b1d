// ISA-18.2 fig. 5 transitions; see alarm_machine.hpp for the states.
#include "alarms/alarm_machine.hpp"

#include <array>

#include "core/error.hpp"

namespace tlsmon {

namespace {

constexpr std::array<std::string_view, 6> kStates{"normal",    "unack",   "ack",
                                                  "rtn_unack", "shelved", "out_of_service"};
constexpr std::array<std::string_view, 4> kLevels{"", "warning", "alert", "alarm"};

// Moves `st` to `to` at `now` and records the event.
void go(AlarmStep& step, IsaState to, AlarmLevel level, std::string kind, AlarmActorKind actor,
        UtcSeconds now) {
    AlarmTransition t{now, std::move(kind), step.state.state, to, level, actor};
    if (to != step.state.state) step.state.since = now;
    step.state.state = to;
    step.state.level = level;
    step.events.push_back(std::move(t));
}

// Leaving shelved / out of service: annunciated afresh if the process is still abnormal.
void resume(AlarmStep& step, std::string kind, AlarmActorKind actor, UtcSeconds now) {
    step.state.shelved_until.reset();
    if (step.state.process != AlarmLevel::none) {
        go(step, IsaState::unack, step.state.process, std::move(kind), actor, now);
    } else {
        go(step, IsaState::normal, AlarmLevel::none, std::move(kind), actor, now);
    }
}

}  // namespace

std::string_view to_string(IsaState s) {
    return kStates[static_cast<std::size_t>(s)];
}
std::string_view to_string(AlarmLevel l) {
    return kLevels[static_cast<std::size_t>(l)];
}
std::string_view to_string(AlarmActorKind a) {
    switch (a) {
        case AlarmActorKind::rule:
            return "rule";
        case AlarmActorKind::scada:
            return "SCADA";
        case AlarmActorKind::cli:
            return "CLI";
        case AlarmActorKind::web:
            return "web";
    }
    return "rule";
}

IsaState parse_isa_state(std::string_view name) {
    for (std::size_t i = 0; i < kStates.size(); ++i) {
        if (kStates[i] == name) return static_cast<IsaState>(i);
    }
    throw Error("unknown alarm state '" + std::string(name) + "'");
}

AlarmLevel parse_alarm_level(std::string_view name) {
    for (std::size_t i = 0; i < kLevels.size(); ++i) {
        if (kLevels[i] == name) return static_cast<AlarmLevel>(i);
    }
    throw Error("unknown alarm level '" + std::string(name) +
                "' (expected \"\", warning, alert or alarm)");
}

AlarmStep expire_shelve(const AlarmMachineState& s, UtcSeconds now) {
    AlarmStep step{s, {}};
    if (s.state == IsaState::shelved && s.shelved_until && *s.shelved_until <= now) {
        resume(step, "shelve_expired", AlarmActorKind::rule, now);
    }
    return step;
}

AlarmStep on_process(const AlarmMachineState& s, AlarmLevel level, bool latching, UtcSeconds now) {
    AlarmStep step = expire_shelve(s, now);
    AlarmMachineState& st = step.state;
    st.process = level;
    const auto rule = AlarmActorKind::rule;
    switch (st.state) {
        case IsaState::shelved:
        case IsaState::out_of_service:
            break;  // suppressed: only the process condition is remembered
        case IsaState::normal:
            if (level != AlarmLevel::none) go(step, IsaState::unack, level, "raise", rule, now);
            break;
        case IsaState::rtn_unack:  // D -> B: abnormal again before the acknowledgement
            if (level != AlarmLevel::none) go(step, IsaState::unack, level, "raise", rule, now);
            break;
        case IsaState::unack:
            if (level == AlarmLevel::none) {
                // B -> D; a latched alarm stays annunciated until acknowledged.
                if (latching) {
                    go(step, IsaState::unack, st.level, "return", rule, now);
                } else {
                    go(step, IsaState::rtn_unack, st.level, "return", rule, now);
                }
            } else if (level > st.level) {
                go(step, IsaState::unack, level, "escalate", rule, now);
            } else if (level < st.level) {
                go(step, IsaState::unack, level, "deescalate", rule, now);
            }
            break;
        case IsaState::ack:
            if (level == AlarmLevel::none) {
                // C -> A; a latched alarm stays until reset by an acknowledgement.
                if (latching) {
                    go(step, IsaState::ack, st.level, "return", rule, now);
                } else {
                    go(step, IsaState::normal, AlarmLevel::none, "clear", rule, now);
                }
            } else if (level > st.level) {
                // A higher level is a new alarm: annunciated and unacknowledged again.
                go(step, IsaState::unack, level, "escalate", rule, now);
            } else if (level < st.level) {
                go(step, IsaState::ack, level, "deescalate", rule, now);
            }
            break;
    }
    return step;
}

AlarmStep on_acknowledge(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now) {
    AlarmStep step = expire_shelve(s, now);
    const AlarmMachineState& st = step.state;
    switch (st.state) {
        case IsaState::unack:
            if (st.process == AlarmLevel::none) {  // latched and returned: ack resets
                go(step, IsaState::normal, AlarmLevel::none, "ack", actor, now);
            } else {
                go(step, IsaState::ack, st.level, "ack", actor, now);
            }
            break;
        case IsaState::ack:
            if (st.process == AlarmLevel::none) {  // latched: the reset
                go(step, IsaState::normal, AlarmLevel::none, "reset", actor, now);
            }
            break;
        case IsaState::rtn_unack:
            go(step, IsaState::normal, AlarmLevel::none, "ack", actor, now);
            break;
        default:
            break;
    }
    return step;
}

AlarmStep on_shelve(const AlarmMachineState& s, UtcSeconds until, AlarmActorKind actor,
                    UtcSeconds now) {
    if (until <= now) {
        throw Error("a shelve ends in the future: " + format_utc(until) + " is not after " +
                    format_utc(now));
    }
    if (until - now > kMaxShelveSeconds) {
        throw Error("a shelve lasts at most 30 days (until " + format_utc(now + kMaxShelveSeconds) +
                    "), not until " + format_utc(until) +
                    "; take the alarm out of service for longer");
    }
    AlarmStep step = expire_shelve(s, now);
    if (step.state.state == IsaState::out_of_service) {
        throw Error("an alarm out of service cannot be shelved; return it to service first");
    }
    step.state.shelved_until = until;
    go(step, IsaState::shelved, AlarmLevel::none, "shelve", actor, now);
    return step;
}

AlarmStep on_unshelve(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now) {
    AlarmStep step = expire_shelve(s, now);
    if (step.state.state == IsaState::shelved) resume(step, "unshelve", actor, now);
    return step;
}

AlarmStep on_remove_from_service(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now) {
    AlarmStep step = expire_shelve(s, now);
    if (step.state.state != IsaState::out_of_service) {
        step.state.shelved_until.reset();
        go(step, IsaState::out_of_service, AlarmLevel::none, "out_of_service", actor, now);
    }
    return step;
}

AlarmStep on_return_to_service(const AlarmMachineState& s, AlarmActorKind actor, UtcSeconds now) {
    AlarmStep step{s, {}};
    if (s.state == IsaState::out_of_service) resume(step, "in_service", actor, now);
    return step;
}

}  // namespace tlsmon
