#pragma once
// One alarm rule: one zone's quantity against up to three levels (warning, alert, alarm),
// each with a high and/or low limit and a deadband, switched on and off only after a number
// of consecutive epochs (on-delay, off-delay), optionally gated by significance (|d| > LoD).
// A rate rule watches the rate of change of the quantity over a time window instead of the
// value (alarm_rate.hpp). Pure: the memory between epochs is returned, the caller keeps it.
#include <array>
#include <optional>
#include <string>

#include "alarms/alarm_machine.hpp"

namespace tlsmon {

struct LevelLimits {
    std::optional<double> high;  // in alarm when value > high
    std::optional<double> low;   // in alarm when value < low
    // Hysteresis (ISA-18.2 "deadband"): an active level clears only once the value is back
    // inside by the deadband: value <= high - deadband and value >= low + deadband.
    double deadband = 0;
};

struct AlarmRuleSpec {
    std::string name;
    std::string zone;
    std::string quantity;  // a stored zone quantity, e.g. "m3c2_median_m"
    // warning, alert, alarm; at least one present.
    std::array<std::optional<LevelLimits>, 3> levels;
    // A level switches on after on_delay + 1 consecutive epochs in alarm, off after
    // off_delay + 1 consecutive epochs back inside (0: at the first epoch).
    int on_delay = 0;
    int off_delay = 0;
    // Only a significant value (|d| > LoD, ZoneResult::significant) counts as in alarm.
    bool significant_only = false;
    // A rate rule: the limits are in mm/day and apply to the least-squares rate of the
    // quantity (metres) over the last window_seconds (alarm_rate.hpp).
    std::optional<double> rate_window_seconds;
    bool latching = false;
    bool enabled = true;
    // Also evaluate epochs that no registration took to the reference's frame (a site that
    // knows its scanner does not move); by default their values raise and clear nothing.
    bool evaluate_unregistered = false;
};

// Checks the rule's own consistency: a level needs a limit, low < high, deadband >= 0 and
// smaller than the level's span, delays >= 0, a positive rate window, and higher levels
// lying beyond lower ones. Returns "" or what is wrong, in words naming the rule key
// (e.g. "levels.alert.deadband must be >= 0").
std::string check_rule(const AlarmRuleSpec& rule);

// What a rule remembers between epochs, per level.
struct LevelTrack {
    bool active = false;  // the level's condition after deadband and delays
    int count = 0;        // consecutive epochs whose raw condition disagrees with `active`
};
struct RuleMemory {
    std::array<LevelTrack, 3> levels;
};
// Stored as text "a:c a:c a:c" (active 0/1, count), e.g. "1:0 0:1 0:0".
std::string to_text(const RuleMemory& m);
RuleMemory rule_memory_from_text(const std::string& text);  // "" -> fresh; bad: Error

// The quality of the epoch a value comes from. Only an accepted epoch is evaluated: a
// rejected, degraded or unregistered one leaves the rule untouched (it neither raises nor
// clears, and does not count toward a delay), unless the rule takes unregistered epochs.
enum class EpochQuality { accepted, degraded, rejected, unregistered };

struct RuleInput {
    double value = 0;  // the quantity (or, for a rate rule, the rate in mm/day)
    bool significant = true;
    EpochQuality quality = EpochQuality::accepted;
};

struct RuleOutcome {
    RuleMemory memory;
    // The process condition: the highest active level; nullopt when not evaluated.
    std::optional<AlarmLevel> level;
};

RuleOutcome evaluate_rule(const AlarmRuleSpec& rule, const RuleMemory& memory,
                          const RuleInput& input);

}  // namespace tlsmon
