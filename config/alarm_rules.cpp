#include "config/alarm_rules.hpp"

#include "config/keys.hpp"

namespace tlsmon {

namespace {

constexpr const char* kLevelKeys[3] = {"warning", "alert", "alarm"};

LevelLimits read_level(TomlFields& t) {
    LevelLimits l;
    for (const char* side : {"high", "low"}) {
        if (!t.has(side)) continue;
        double v = 0;
        t.get(side, v, -1e9, 1e9);
        (std::string(side) == "high" ? l.high : l.low) = v;
    }
    t.get("deadband", l.deadband, 0, 1e9);
    t.reject_unknown_keys();
    return l;
}

AlarmRuleSpec read_rule(TomlFields& t, const std::set<std::string>& zones,
                        const std::set<std::string>& quantities,
                        const std::set<std::string>& taken) {
    AlarmRuleSpec r;
    for (const char* key : {"name", "zone", "quantity"}) {
        if (!t.has(key)) t.fail(key, "every [[alarm.rule]] needs name, zone and quantity");
    }
    t.get("name", r.name);
    if (r.name.empty()) t.fail("name", "expected a non-empty rule name");
    if (r.name.rfind("system.", 0) == 0) {
        t.fail("name", "names beginning with 'system.' are the system alarms'");
    }
    if (taken.count(r.name)) t.fail("name", "rule '" + r.name + "' is defined twice");
    t.get("zone", r.zone);
    if (!zones.count(r.zone)) {
        std::string names;
        for (const auto& z : zones) names += (names.empty() ? "" : ", ") + z;
        t.fail("zone", "no [[zone]] named '" + r.zone +
                           "' (zones: " + (names.empty() ? "none" : names) + ")");
    }
    t.get("quantity", r.quantity);
    if (r.quantity.empty()) t.fail("quantity", "expected a quantity name, e.g. m3c2_median_m");
    if (!quantities.count(r.quantity)) {  // a misspelt quantity would never fire
        std::string names;
        for (const auto& q : quantities) names += (names.empty() ? "" : ", ") + q;
        t.fail("quantity", "no configured stage produces '" + r.quantity +
                               "' (quantities: " + (names.empty() ? "none" : names) + ")");
    }
    t.get("on_delay", r.on_delay, 0, 1000);
    t.get("off_delay", r.off_delay, 0, 1000);
    t.get("significant_only", r.significant_only);
    t.get("latching", r.latching);
    t.get("enabled", r.enabled);
    t.get("evaluate_unregistered", r.evaluate_unregistered);
    if (t.has("rate_window")) {
        double w = 0;
        t.get_seconds("rate_window", w, 60, 365 * 86400.0);
        r.rate_window_seconds = w;
    }
    for (int k = 0; k < 3; ++k) {
        if (auto level = t.table(kLevelKeys[k])) r.levels[k] = read_level(*level);
    }
    // The rule's own consistency; the message names the key, placed at the rule's name.
    const std::string wrong = check_rule(r);
    if (!wrong.empty()) {
        std::string key = wrong.substr(0, wrong.find(' '));  // "levels.alert.deadband"
        if (key.rfind("levels.", 0) == 0) key = key.substr(7);
        if (key == "a") key = "name";
        std::string what =
            wrong;  // "levels.alert.high ... levels.warning.high" -> "alert.high ..."
        for (auto at = what.find("levels."); at != std::string::npos; at = what.find("levels.")) {
            what.erase(at, 7);
        }
        t.fail(key, what);
    }
    t.reject_unknown_keys();
    return r;
}

std::string limits_text(const LevelLimits& l) {
    std::string s = "{ ";
    if (l.high) s += "high = " + toml_number(*l.high) + ", ";
    if (l.low) s += "low = " + toml_number(*l.low) + ", ";
    return s + "deadband = " + toml_number(l.deadband) + " }";
}

}  // namespace

std::vector<AlarmRuleSpec> read_alarm_rules(TomlFields& alarm, const std::set<std::string>& zones,
                                            const std::set<std::string>& quantities) {
    std::vector<AlarmRuleSpec> rules;
    std::set<std::string> names;
    for (auto& t : alarm.array_of_tables("rule")) {
        rules.push_back(read_rule(t, zones, quantities, names));
        names.insert(rules.back().name);
    }
    return rules;
}

std::string describe_alarm_rule(const AlarmRuleSpec& r) {
    std::string s = "alarm rule " + toml_string(r.name) + ": zone = " + toml_string(r.zone) +
                    ", quantity = " + toml_string(r.quantity) +
                    ", on_delay = " + std::to_string(r.on_delay) +
                    ", off_delay = " + std::to_string(r.off_delay) +
                    ", significant_only = " + (r.significant_only ? "true" : "false") +
                    ", latching = " + (r.latching ? "true" : "false") +
                    ", enabled = " + (r.enabled ? "true" : "false") +
                    ", evaluate_unregistered = " + (r.evaluate_unregistered ? "true" : "false");
    if (r.rate_window_seconds) s += ", rate_window = " + toml_number(*r.rate_window_seconds);
    for (int k = 0; k < 3; ++k) {
        if (r.levels[k]) s += std::string(", ") + kLevelKeys[k] + " = " + limits_text(*r.levels[k]);
    }
    return s;
}

}  // namespace tlsmon
