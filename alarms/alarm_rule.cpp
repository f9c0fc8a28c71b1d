// Level limits with deadband and consecutive-epoch delays; see alarm_rule.hpp.
#include "alarms/alarm_rule.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tlsmon {

namespace {

constexpr std::array<const char*, 3> kLevelNames{"warning", "alert", "alarm"};

// The raw condition of one level: beyond the limit, or, once active, not yet back inside
// by the deadband.
bool beyond(const LevelLimits& l, bool active, double v) {
    const double band = active ? l.deadband : 0.0;
    if (l.high && v > *l.high - band) return true;
    if (l.low && v < *l.low + band) return true;
    return false;
}

}  // namespace

std::string check_rule(const AlarmRuleSpec& r) {
    bool any = false;
    for (std::size_t k = 0; k < 3; ++k) {
        if (!r.levels[k]) continue;
        any = true;
        const auto& l = *r.levels[k];
        const std::string key = std::string("levels.") + kLevelNames[k];
        if (!l.high && !l.low) return key + " needs a high or a low limit";
        if ((l.high && !std::isfinite(*l.high)) || (l.low && !std::isfinite(*l.low))) {
            return key + " limits must be finite numbers";
        }
        if (l.high && l.low && !(*l.low < *l.high)) return key + ".low must be below .high";
        if (!(l.deadband >= 0) || !std::isfinite(l.deadband)) {
            return key + ".deadband must be >= 0";
        }
        if (l.high && l.low && !(2 * l.deadband < *l.high - *l.low)) {
            return key + ".deadband must be less than half of high - low";
        }
        // A higher level lies beyond the lower ones on the same side.
        for (std::size_t j = 0; j < k; ++j) {
            if (!r.levels[j]) continue;
            const auto& lo = *r.levels[j];
            if (l.high && lo.high && !(*l.high > *lo.high)) {
                return key + ".high must be above levels." + kLevelNames[j] + ".high";
            }
            if (l.low && lo.low && !(*l.low < *lo.low)) {
                return key + ".low must be below levels." + kLevelNames[j] + ".low";
            }
        }
    }
    if (!any) return "a rule needs at least one of levels.warning, levels.alert, levels.alarm";
    if (r.on_delay < 0) return "on_delay must be >= 0 epochs";
    if (r.off_delay < 0) return "off_delay must be >= 0 epochs";
    if (r.rate_window_seconds && !(*r.rate_window_seconds > 0)) {
        return "rate_window must be a positive duration";
    }
    if (r.rate_window_seconds && r.significant_only) {
        return "significant_only applies to value rules, not to a rate rule";
    }
    return "";
}

std::string to_text(const RuleMemory& m) {
    std::ostringstream out;
    for (std::size_t k = 0; k < 3; ++k) {
        out << (k ? " " : "") << (m.levels[k].active ? 1 : 0) << ':' << m.levels[k].count;
    }
    return out.str();
}

RuleMemory rule_memory_from_text(const std::string& text) {
    RuleMemory m;
    if (text.empty()) return m;
    std::istringstream in(text);
    for (auto& l : m.levels) {
        int active = 0;
        char colon = 0;
        if (!(in >> active >> colon >> l.count) || colon != ':' || (active != 0 && active != 1) ||
            l.count < 0) {
            throw Error("alarm rule memory '" + text + "' is not \"a:c a:c a:c\"");
        }
        l.active = active == 1;
    }
    return m;
}

RuleOutcome evaluate_rule(const AlarmRuleSpec& rule, const RuleMemory& memory,
                          const RuleInput& input) {
    RuleOutcome out{memory, std::nullopt};
    if (input.quality != EpochQuality::accepted || !std::isfinite(input.value)) return out;
    const bool counts = !rule.significant_only || input.significant;
    AlarmLevel level = AlarmLevel::none;
    for (std::size_t k = 0; k < 3; ++k) {
        LevelTrack& t = out.memory.levels[k];
        if (!rule.levels[k]) {
            t = {};
            continue;
        }
        const bool raw = counts && beyond(*rule.levels[k], t.active, input.value);
        if (raw == t.active) {
            t.count = 0;
        } else {
            ++t.count;
            const int delay = t.active ? rule.off_delay : rule.on_delay;
            if (t.count > delay) {
                t.active = raw;
                t.count = 0;
            }
        }
        if (t.active) level = static_cast<AlarmLevel>(k + 1);
    }
    out.level = level;
    return out;
}

}  // namespace tlsmon
