#include "alarms/rule_step.hpp"

namespace tlsmon {

RuleStepResult step_rule(const AlarmRuleSpec& rule, const AlarmRuleStatus& status,
                         const std::optional<RuleInput>& input, UtcSeconds acquired) {
    RuleStepResult out{status, {}, false, false};
    if (!rule.enabled) return out;
    if (status.evaluated && acquired < *status.evaluated) {
        out.late = true;
        return out;
    }
    AlarmStep step;
    const auto outcome =
        input ? evaluate_rule(rule, status.memory, *input) : RuleOutcome{status.memory, {}};
    if (outcome.level) {
        step = on_process(status.machine, *outcome.level, rule.latching, acquired);
        out.status.memory = outcome.memory;
        out.status.evaluated = acquired;
        out.evaluated = true;
    } else {
        step = expire_shelve(status.machine, acquired);
    }
    out.status.machine = step.state;
    out.events = std::move(step.events);
    return out;
}

}  // namespace tlsmon
