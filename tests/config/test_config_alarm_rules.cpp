// [[alarm.rule]] tables: read into AlarmRuleSpec, every mistake an error naming the key.
#include <gtest/gtest.h>

#include "config/config.hpp"

namespace tlsmon {
namespace {

const std::string kZone = "[[zone]]\nname = \"pier P3 top\"\nmin = [0, 0, 0]\nmax = [1, 1, 10]\n";

Config parse(const std::string& rules) {
    return parse_config(kZone + rules, "site.toml", "/tmp");
}

std::string error_of(const std::string& rules) {
    try {
        parse(rules);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(ConfigAlarmRules, ReadsEveryKey) {
    const Config c = parse(
        "[alarm]\ncadence = \"10min\"\nstale_factor = 4\n"
        "[[alarm.rule]]\nname = \"P3 settlement\"\nzone = \"pier P3 top\"\n"
        "quantity = \"m3c2_median_m\"\non_delay = 2\noff_delay = 1\nsignificant_only = true\n"
        "latching = true\n"
        "warning = { high = 0.005, deadband = 0.001 }\n"
        "alert = { high = 0.008, low = -0.008, deadband = 0.001 }\n"
        "alarm = { high = 0.010, deadband = 0.002 }\n"
        "[[alarm.rule]]\nname = \"P3 rate\"\nzone = \"pier P3 top\"\n"
        "quantity = \"m3c2_median_m\"\nrate_window = \"24h\"\nalert = { high = 2.0 }\n");
    EXPECT_EQ(c.alarm.cadence, 600);
    EXPECT_EQ(c.alarm.stale_factor, 4);
    ASSERT_EQ(c.alarm.rules.size(), 2u);
    const auto& r = c.alarm.rules[0];
    EXPECT_EQ(r.name, "P3 settlement");
    EXPECT_EQ(r.on_delay, 2);
    EXPECT_EQ(r.off_delay, 1);
    EXPECT_TRUE(r.significant_only);
    EXPECT_TRUE(r.latching);
    EXPECT_DOUBLE_EQ(*r.levels[0]->high, 0.005);
    EXPECT_FALSE(r.levels[0]->low);
    EXPECT_DOUBLE_EQ(*r.levels[1]->low, -0.008);
    EXPECT_DOUBLE_EQ(r.levels[2]->deadband, 0.002);
    EXPECT_EQ(c.alarm.rules[1].rate_window_seconds, 86400);
    EXPECT_EQ(pipeline_config(c).alarm_rules.size(), 2u);
}

TEST(ConfigAlarmRules, MistakesNameTheKey) {
    const std::string head =
        "[[alarm.rule]]\nname = \"r\"\nzone = \"pier P3 top\"\nquantity = \"m3c2_median_m\"\n";
    EXPECT_NE(error_of("[[alarm.rule]]\nname = \"r\"\n").find("key 'alarm.rule[0].zone'"),
              std::string::npos);
    EXPECT_NE(error_of(head + "alert = { high = 0.01, deadband = -1 }\n")
                  .find("key 'alarm.rule[0].alert.deadband'"),
              std::string::npos)
        << error_of(head + "alert = { high = 0.01, deadband = -1 }\n");
    EXPECT_NE(error_of(head + "alert = { high = 0.01, dead_band = 1 }\n")
                  .find("alarm.rule[0].alert.dead_band"),
              std::string::npos);
    const auto order = error_of(head + "warning = { high = 0.02 }\nalert = { high = 0.01 }\n");
    EXPECT_NE(order.find("alert.high must be above warning.high"), std::string::npos) << order;
    EXPECT_NE(error_of(head).find("needs at least one of"), std::string::npos);
    const auto zone = error_of(
        "[[alarm.rule]]\nname = \"r\"\nzone = \"P4\"\nquantity = \"m3c2_median_m\"\n"
        "alarm = { high = 1 }\n");
    EXPECT_NE(zone.find("no [[zone]] named 'P4' (zones: pier P3 top)"), std::string::npos) << zone;
    EXPECT_NE(error_of(head + "alarm = { high = 1 }\n" + head + "alarm = { high = 1 }\n")
                  .find("rule 'r' is defined twice"),
              std::string::npos);
    EXPECT_NE(error_of(head + "on_delay = -1\nalarm = { high = 1 }\n")
                  .find("key 'alarm.rule[0].on_delay'"),
              std::string::npos);
    EXPECT_NE(
        error_of(head + "alarm = { high = 1 }\nsignificant_only = true\nrate_window = \"1h\"\n")
            .find("significant_only applies to value rules"),
        std::string::npos);
    // The line of the rule is named.
    EXPECT_NE(error_of(head + "alarm = { high = 1, low = 2 }\n").find("site.toml:"),
              std::string::npos);
}

// A misspelt quantity was accepted and the rule never fired: it must name what a configured
// stage writes, and the error lists those.
TEST(ConfigAlarmRules, QuantityMustBeOneAConfiguredStageWrites) {
    const std::string rule =
        "[[alarm.rule]]\nname = \"r\"\nzone = \"pier P3 top\"\nalarm = { high = 1 }\n";
    auto e = error_of(rule + "quantity = \"m3c2_medain_m\"\n");
    EXPECT_NE(e.find("key 'alarm.rule[0].quantity'"), std::string::npos) << e;
    EXPECT_NE(e.find("no configured stage produces 'm3c2_medain_m'"), std::string::npos) << e;
    EXPECT_NE(e.find("m3c2_median_m"), std::string::npos) << e;
    EXPECT_NE(e.find("keypoint_along_surface_h_m"), std::string::npos) << e;
    // A stage switched off produces nothing.
    e = error_of("[keypoints]\nenabled = false\n" + rule + "quantity = \"keypoint_dz_m\"\n");
    EXPECT_NE(e.find("no configured stage produces 'keypoint_dz_m'"), std::string::npos) << e;
    EXPECT_EQ(e.find("keypoint_dx_m"), std::string::npos) << e;
    EXPECT_EQ(parse(rule + "quantity = \"keypoint_dz_m\"\n").alarm.rules.at(0).quantity,
              "keypoint_dz_m");
    // A zone's plane series exists with the registration on planes only.
    e = error_of(rule + "quantity = \"plane_shift_m\"\n");
    EXPECT_NE(e.find("no configured stage produces 'plane_shift_m'"), std::string::npos) << e;
    EXPECT_EQ(
        parse("[registration]\nmethod = \"planes\"\n" + rule + "quantity = \"plane_shift_m\"\n")
            .alarm.rules.at(0)
            .quantity,
        "plane_shift_m");
    // The Modbus registers' quantities likewise (NaN for ever otherwise).
    e = error_of("[modbus]\nquantities = [\"m3c2_median\"]\n");
    EXPECT_NE(e.find("key 'modbus.quantities'"), std::string::npos) << e;
    EXPECT_NE(e.find("no stage produces 'm3c2_median'"), std::string::npos) << e;
}

// A rule takes unregistered epochs only when it says so.
TEST(ConfigAlarmRules, EvaluateUnregisteredIsOffUnlessSet) {
    const std::string rule =
        "[[alarm.rule]]\nname = \"r\"\nzone = \"pier P3 top\"\nquantity = \"m3c2_median_m\"\n"
        "alarm = { high = 1 }\n";
    EXPECT_FALSE(parse(rule).alarm.rules.at(0).evaluate_unregistered);
    EXPECT_TRUE(
        parse(rule + "evaluate_unregistered = true\n").alarm.rules.at(0).evaluate_unregistered);
}

}  // namespace
}  // namespace tlsmon
