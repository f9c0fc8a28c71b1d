#pragma once
// The [[alarm.rule]] tables of the configuration (docs/alarms.md):
//
//   [[alarm.rule]]
//   name = "P3 settlement"             # unique
//   zone = "pier P3 top"               # a [[zone]]
//   quantity = "m3c2_median_m"         # a zone quantity of the time series
//   on_delay = 2                       # epochs beyond the first (0: at once)
//   off_delay = 1
//   significant_only = true            # only |d| > LoD counts
//   latching = false
//   enabled = true
//   rate_window = "24h"                # optional: a rate rule, limits in mm/day
//   warning = { high = 0.005, deadband = 0.001 }
//   alert = { high = 0.008, low = -0.008, deadband = 0.001 }
//   alarm = { high = 0.010, deadband = 0.002 }
#include <set>
#include <string>
#include <vector>

#include "alarms/alarm_rule.hpp"
#include "core/toml_fields.hpp"

namespace tlsmon {

// Reads every [[alarm.rule]] of the [alarm] table; each mistake is a ConfigError naming the
// file, line and key ("alarm.rule.alert.deadband"). A rule names one of `zones` and one of
// `quantities` (those the configured stages write).
std::vector<AlarmRuleSpec> read_alarm_rules(TomlFields& alarm, const std::set<std::string>& zones,
                                            const std::set<std::string>& quantities);

// The rule as one line of the effective configuration.
std::string describe_alarm_rule(const AlarmRuleSpec& rule);

}  // namespace tlsmon
