#pragma once
// One rule, one epoch: the rule's evaluation (alarm_rule.hpp) feeding its state machine
// (alarm_machine.hpp), at the epoch's acquisition time. Epochs are evaluated in acquisition
// order: an epoch acquired before the newest one the rule has evaluated (a scan that
// arrived late) leaves the rule untouched and is reported as `late`.
#include <optional>
#include <vector>

#include "alarms/alarm_machine.hpp"
#include "alarms/alarm_rule.hpp"

namespace tlsmon {

struct AlarmRuleStatus {
    AlarmMachineState machine;
    RuleMemory memory;
    std::optional<UtcSeconds> evaluated;  // acquisition time of the newest epoch evaluated
};

struct RuleStepResult {
    AlarmRuleStatus status;
    std::vector<AlarmTransition> events;
    bool evaluated = false;  // the rule took the epoch's value
    bool late = false;       // acquired before the newest epoch already evaluated
};

// `input`: the rule's value in this epoch, nullopt when the epoch has none (then only a
// shelve may expire). A disabled rule does nothing.
RuleStepResult step_rule(const AlarmRuleSpec& rule, const AlarmRuleStatus& status,
                         const std::optional<RuleInput>& input, UtcSeconds acquired);

}  // namespace tlsmon
