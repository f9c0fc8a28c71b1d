// Rule evaluation against analytic series: limits, deadband, on/off delays, gating, levels;
// rate of change against an exact linear series; system alarm conditions.
#include <gtest/gtest.h>

#include "alarms/alarm_rate.hpp"
#include "alarms/alarm_rule.hpp"
#include "alarms/system_alarms.hpp"
#include "core/error.hpp"

namespace tlsmon {
namespace {

using L = AlarmLevel;

AlarmRuleSpec high_rule(double warning, double alarm, double deadband, int on, int off) {
    AlarmRuleSpec r;
    r.name = "pier_top";
    r.levels[0] = LevelLimits{warning, std::nullopt, deadband};
    r.levels[2] = LevelLimits{alarm, std::nullopt, deadband};
    r.on_delay = on;
    r.off_delay = off;
    return r;
}

// Runs the series through the rule; the level after each epoch.
std::vector<L> run(const AlarmRuleSpec& r, const std::vector<double>& values,
                   bool significant = true) {
    RuleMemory m;
    std::vector<L> out;
    for (double v : values) {
        const auto o = evaluate_rule(r, m, {v, significant, EpochQuality::accepted});
        m = o.memory;
        out.push_back(o.level.value());
    }
    return out;
}

TEST(AlarmRule, LevelsWithoutDelayFollowTheLimits) {
    const auto r = high_rule(0.005, 0.010, 0, 0, 0);
    EXPECT_EQ(run(r, {0.004, 0.006, 0.011, 0.007, 0.001}),
              (std::vector<L>{L::none, L::warning, L::alarm, L::warning, L::none}));
}

TEST(AlarmRule, ExactlyAtTheLimitIsNotBeyond) {
    const auto r = high_rule(0.005, 0.010, 0, 0, 0);
    EXPECT_EQ(run(r, {0.005}), (std::vector<L>{L::none}));
}

TEST(AlarmRule, DeadbandHoldsAnActiveLevelUntilBackInsideByTheBand) {
    // warning at 5 mm, deadband 1 mm: on above 5, off only at or below 4.
    const auto r = high_rule(0.005, 0.010, 0.001, 0, 0);
    EXPECT_EQ(run(r, {0.0045, 0.0051, 0.0045, 0.00401, 0.0040, 0.0045}),
              (std::vector<L>{L::none, L::warning, L::warning, L::warning, L::none, L::none}));
}

TEST(AlarmRule, LowLimit) {
    AlarmRuleSpec r;
    r.levels[1] = LevelLimits{std::nullopt, -0.003, 0.0005};
    EXPECT_EQ(run(r, {-0.002, -0.0031, -0.0026, -0.0025}),
              (std::vector<L>{L::none, L::alert, L::alert, L::none}));
}

TEST(AlarmRule, OnDelayNeedsOnDelayPlusOneConsecutiveEpochs) {
    // A step at epoch 3 with on_delay 2: the warning comes at epoch 5 (= 3 + 2), none before.
    const auto r = high_rule(0.005, 0.010, 0, 2, 0);
    EXPECT_EQ(
        run(r, {0, 0, 0, 0.006, 0.006, 0.006, 0.006}),
        (std::vector<L>{L::none, L::none, L::none, L::none, L::none, L::warning, L::warning}));
}

TEST(AlarmRule, AnInterruptedRunRestartsTheOnDelay) {
    const auto r = high_rule(0.005, 0.010, 0, 2, 0);
    EXPECT_EQ(run(r, {0.006, 0.006, 0.004, 0.006, 0.006, 0.006}),
              (std::vector<L>{L::none, L::none, L::none, L::none, L::none, L::warning}));
}

TEST(AlarmRule, OffDelayNeedsOffDelayPlusOneConsecutiveEpochs) {
    const auto r = high_rule(0.005, 0.010, 0, 0, 1);
    EXPECT_EQ(run(r, {0.006, 0.004, 0.006, 0.004, 0.004, 0.004}),
              (std::vector<L>{L::warning, L::warning, L::warning, L::warning, L::none, L::none}));
}

TEST(AlarmRule, GatingIgnoresValuesBelowTheLoD) {
    auto r = high_rule(0.005, 0.010, 0, 0, 0);
    r.significant_only = true;
    EXPECT_EQ(run(r, {0.02, 0.02}, false), (std::vector<L>{L::none, L::none}));
    EXPECT_EQ(run(r, {0.02}, true), (std::vector<L>{L::alarm}));
}

TEST(AlarmRule, RejectedAndDegradedEpochsAreNotEvaluated) {
    const auto r = high_rule(0.005, 0.010, 0, 1, 0);
    RuleMemory m;
    auto o = evaluate_rule(r, m, {0.02, true, EpochQuality::accepted});
    EXPECT_EQ(o.level, L::none);  // first of two epochs
    for (auto q : {EpochQuality::rejected, EpochQuality::degraded}) {
        const auto skipped = evaluate_rule(r, o.memory, {0.02, true, q});
        EXPECT_FALSE(skipped.level);
        EXPECT_EQ(to_text(skipped.memory), to_text(o.memory));
    }
    o = evaluate_rule(r, o.memory, {0.02, true, EpochQuality::accepted});
    EXPECT_EQ(o.level, L::alarm);
}

TEST(AlarmRule, MemoryRoundTripsThroughText) {
    RuleMemory m;
    m.levels[0] = {true, 0};
    m.levels[2] = {false, 3};
    EXPECT_EQ(to_text(m), "1:0 0:0 0:3");
    EXPECT_EQ(to_text(rule_memory_from_text("1:0 0:0 0:3")), "1:0 0:0 0:3");
    EXPECT_EQ(to_text(rule_memory_from_text("")), "0:0 0:0 0:0");
    EXPECT_THROW(rule_memory_from_text("1:0 2:0 0:0"), Error);
}

TEST(AlarmRule, CheckNamesTheKey) {
    AlarmRuleSpec r;
    EXPECT_NE(check_rule(r).find("at least one"), std::string::npos);
    r.levels[1] = LevelLimits{0.01, std::nullopt, -1};
    EXPECT_EQ(check_rule(r), "levels.alert.deadband must be >= 0");
    r.levels[1]->deadband = 0;
    r.levels[0] = LevelLimits{0.02, std::nullopt, 0};
    EXPECT_EQ(check_rule(r), "levels.alert.high must be above levels.warning.high");
    r.levels[0]->high = 0.005;
    EXPECT_EQ(check_rule(r), "");
    r.on_delay = -1;
    EXPECT_EQ(check_rule(r), "on_delay must be >= 0 epochs");
    r.on_delay = 0;
    r.levels[2] = LevelLimits{0.03, 0.05, 0};
    EXPECT_EQ(check_rule(r), "levels.alarm.low must be below .high");
}

TEST(AlarmRate, LinearSeriesGivesItsSlopeInMmPerDay) {
    // v = 2 mm/day * t, one point every 15 min over 2 days; window 1 day.
    std::vector<TimedValue> pts;
    const UtcSeconds t0 = 1772366400;
    for (int k = 0; k <= 192; ++k) {
        const UtcSeconds t = t0 + 900 * k;
        pts.push_back({t, 0.002 * (900.0 * k) / 86400.0});
    }
    const auto rate = rate_mm_per_day(pts, t0 + 900 * 192, 86400);
    ASSERT_TRUE(rate);
    EXPECT_NEAR(*rate, 2.0, 1e-9);
}

TEST(AlarmRate, OnlyTheWindowCounts) {
    // Flat for a day, then 5 mm/day: a 6 h window sees only the ramp.
    std::vector<TimedValue> pts;
    const UtcSeconds t0 = 0;
    for (int h = 0; h <= 24; ++h) pts.push_back({t0 + 3600 * h, 0.0});
    for (int h = 25; h <= 30; ++h) pts.push_back({t0 + 3600 * h, 0.005 * (h - 24) / 24.0});
    EXPECT_NEAR(*rate_mm_per_day(pts, t0 + 30 * 3600, 6 * 3600), 5.0, 1e-9);
    EXPECT_FALSE(rate_mm_per_day(pts, t0 + 30 * 3600, 1800));  // one point only
}

TEST(SystemAlarms, StaleAfterKTimesTheCadence) {
    SystemAlarmConfig c;  // 900 s, factor 3
    SystemObservation seen;
    seen.last_epoch_acquired = 1000;
    seen.now = 1000 + 2700;
    EXPECT_FALSE(system_conditions(c, seen, {})[0]);
    seen.now = 1000 + 2701;
    EXPECT_TRUE(system_conditions(c, seen, {})[0]);
}

TEST(SystemAlarms, DiskNearlyFullHasADeadband) {
    SystemAlarmConfig c;  // 5 %, deadband 1 %
    SystemObservation seen;
    seen.disk_free_fraction = 0.049;
    auto on = system_conditions(c, seen, {});
    EXPECT_TRUE(on[3]);
    seen.disk_free_fraction = 0.055;
    EXPECT_TRUE(system_conditions(c, seen, on)[3]);
    seen.disk_free_fraction = 0.061;
    EXPECT_FALSE(system_conditions(c, seen, on)[3]);
}

TEST(SystemAlarms, EpochOutcomesAndDatabase) {
    SystemObservation seen;
    seen.last_epoch_rejected = true;
    seen.last_epoch_failed = false;
    seen.database_error = true;
    const auto c = system_conditions({}, seen, {false, false, true, false, false});
    EXPECT_TRUE(c[1]);
    EXPECT_FALSE(c[2]);
    EXPECT_TRUE(c[4]);
    EXPECT_EQ(rule_name(SystemAlarm::stale), "system.stale");
    EXPECT_EQ(system_alarm_level(SystemAlarm::registration_rejected), L::warning);
}

}  // namespace
}  // namespace tlsmon

#include "alarms/rule_step.hpp"

namespace tlsmon {
namespace {

TEST(RuleStep, StepSeriesRaisesWithinOnDelayPlusOneEpochsAndNoneBefore) {
    AlarmRuleSpec r;
    r.levels[2] = LevelLimits{0.010, std::nullopt, 0.002};
    r.on_delay = 2;
    AlarmRuleStatus st;
    const UtcSeconds t0 = 1772366400;
    // 0 mm for 4 epochs, then a 12 mm step at epoch 4: raised at epoch 4 + 2 = 6.
    for (int k = 0; k < 8; ++k) {
        const double v = k < 4 ? 0.0 : 0.012;
        const auto s = step_rule(r, st, RuleInput{v, true, EpochQuality::accepted}, t0 + 900 * k);
        st = s.status;
        if (k < 6) {
            EXPECT_EQ(st.machine.state, IsaState::normal) << "epoch " << k;
            EXPECT_TRUE(s.events.empty());
        } else if (k == 6) {
            ASSERT_EQ(s.events.size(), 1u);
            EXPECT_EQ(s.events[0].kind, "raise");
            EXPECT_EQ(s.events[0].time, t0 + 900 * 6);
            EXPECT_EQ(st.machine.level, AlarmLevel::alarm);
        }
    }
    EXPECT_EQ(st.machine.state, IsaState::unack);
}

TEST(RuleStep, LateEpochLeavesTheRuleUntouched) {
    AlarmRuleSpec r;
    r.levels[0] = LevelLimits{0.005, std::nullopt, 0};
    AlarmRuleStatus st;
    st.evaluated = 2000;
    const auto s = step_rule(r, st, RuleInput{0.02, true, EpochQuality::accepted}, 1999);
    EXPECT_TRUE(s.late);
    EXPECT_FALSE(s.evaluated);
    EXPECT_EQ(s.status.machine.state, IsaState::normal);
}

TEST(RuleStep, NoValueOnlyExpiresAShelve) {
    AlarmRuleSpec r;
    r.levels[0] = LevelLimits{0.005, std::nullopt, 0};
    AlarmRuleStatus st;
    st.machine = {IsaState::shelved, AlarmLevel::none, AlarmLevel::warning, 0, 100};
    auto s = step_rule(r, st, std::nullopt, 50);
    EXPECT_EQ(s.status.machine.state, IsaState::shelved);
    s = step_rule(r, st, std::nullopt, 100);
    EXPECT_EQ(s.status.machine.state, IsaState::unack);
    EXPECT_FALSE(s.evaluated);
}

}  // namespace
}  // namespace tlsmon
