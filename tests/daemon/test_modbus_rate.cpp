// The Modbus `.rate` registers show the rate an alarm fires on: the same function
// (alarms/alarm_rate.hpp) over the same window. The pipeline processes a plane rising by
// uneven steps every 15 min (M3C2 in one zone, a rate rule over 2 h); after each epoch the
// snapshot's rate of the zone's m3c2_median_m, in m/day, is the rule's stored value in
// mm/day / 1000 — and differs from the rate over a day, which it showed before.
#include <gtest/gtest.h>

#include "alarms/alarm_rate.hpp"
#include "daemon/modbus/modbus_snapshot.hpp"
#include "pipeline/alarm_evaluation.hpp"
#include "tests/pipeline/pipeline_site.hpp"

namespace tlsmon::test {
namespace {

TEST(ModbusRate, IsTheRateTheAlarmRuleEvaluates) {
    PipelineSite site;
    site.config.m3c2.zones = {box_zone("deck", {-0.1, -0.1, -1.0}, {10.1, 10.1, 1.0})};
    site.config.m3c2.orient_to_scanner = false;  // normals up: a rise is positive
    site.config.m3c2.cylinder_radius = 1.0;
    site.config.m3c2.min_points = 5;
    site.config.zones = site.config.m3c2.zones;
    site.db->site().upsert_zone("deck", "{}");
    AlarmRuleSpec rule;
    rule.name = "deck_rising";
    rule.zone = "deck";
    rule.quantity = "m3c2_median_m";
    rule.levels[0] = LevelLimits{1e9, std::nullopt, 0};
    rule.rate_window_seconds = 7200;
    rule.evaluate_unregistered = true;  // plain XYZ planes: no registration
    site.config.alarm_rules = {rule};
    store_alarm_rules(*site.db, site.config.alarm_rules);

    ModbusConfig modbus;
    modbus.quantities = {"m3c2_median_m"};
    const double heights[] = {0.0,    0.001, 0.0015, 0.004,  0.0042, 0.006,
                              0.0061, 0.009, 0.0093, 0.0094, 0.012,  0.0125};
    ReferenceCache cache(*site.db);
    const UtcSeconds t0 = 1767225600;  // 2026-01-01T00:00:00Z
    std::vector<TimedValue> stored;
    int compared = 0;
    for (int k = 0; k < 12; ++k) {
        const UtcSeconds t = t0 + 900 * k;
        const Epoch e = site.add_epoch("e" + std::to_string(k) + ".xyz", t, heights[k]);
        ASSERT_EQ(site.process(e, cache), EpochOutcome::done);
        const auto inputs = modbus_map_inputs(&*site.db, {"deck"}, modbus);
        const ModbusSnapshot snapshot = read_modbus_snapshot(*site.db, inputs, modbus, t + 60);
        ASSERT_EQ(snapshot.values.size(), 1u);
        const auto states = site.db->alarms().states();
        const auto points = site.db->series().points("deck", "m3c2_median_m", {});
        ASSERT_EQ(points.size(), static_cast<std::size_t>(k + 1));
        if (k == 0) {
            EXPECT_FALSE(snapshot.values[0].rate);  // one value: no rate
            continue;
        }
        ASSERT_TRUE(snapshot.values[0].rate);
        ASSERT_EQ(states.size(), 1u);
        ASSERT_TRUE(states[0].value);
        EXPECT_NEAR(*snapshot.values[0].rate * 1000.0, *states[0].value, 1e-9) << "epoch " << k;
        ++compared;
        // The rise is about 1 mm per 15 min: ≈ 0.1 m/day.
        EXPECT_GT(*snapshot.values[0].rate, 0.05);
        if (k == 11) {
            std::vector<TimedValue> all;
            for (const auto& p : points) all.push_back({p.acquired, p.value});
            const double over_a_day = *rate_per_day(all, t, 86400);
            EXPECT_GT(std::abs(over_a_day - *snapshot.values[0].rate), 1e-4);
        }
    }
    EXPECT_EQ(compared, 11);
}

}  // namespace
}  // namespace tlsmon::test
