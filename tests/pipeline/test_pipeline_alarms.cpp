// The alarm evaluation runs in the real pipeline's commit (process_epoch): no stage writes
// zone results yet, so the configured rules take no value, but a shelve whose expiry lies
// before the epoch's acquisition ends in that epoch's commit, at its acquisition time.
#include <gtest/gtest.h>

#include "pipeline/alarm_evaluation.hpp"
#include "pipeline_site.hpp"

namespace tlsmon::test {
namespace {

TEST(PipelineAlarms, TheEpochCommitEvaluatesTheRulesAtTheAcquisitionTime) {
    PipelineSite site;
    AlarmRuleSpec rule;
    rule.name = "P3 settlement";
    rule.zone = "pier P3 top";
    rule.quantity = "m3c2_median_m";
    rule.levels[2] = LevelLimits{0.010, std::nullopt, 0.002};
    site.config.alarm_rules = {rule};
    site.db->site().upsert_zone("pier P3 top", "{}");
    store_alarm_rules(*site.db, site.config.alarm_rules);
    // Shelved until 1500 while its condition (alarm) stands.
    site.db->alarms().set_state(
        {rule.name, "shelved", "", 500, 0.012, std::nullopt, "alarm", 1500, "0:0 0:0 1:0", 500});

    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.01);
    ReferenceCache cache(*site.db);
    EXPECT_EQ(site.process(e0, cache), EpochOutcome::done);
    EXPECT_EQ(site.db->alarms().states().at(0).state, "shelved");  // 1000 < 1500
    EXPECT_EQ(site.process(e1, cache), EpochOutcome::done);
    const auto s = site.db->alarms().states().at(0);
    EXPECT_EQ(s.state, "unack");  // the standing alarm annunciated afresh
    EXPECT_EQ(s.level, "alarm");
    EXPECT_EQ(s.since, 2000);
    EXPECT_EQ(s.memory, "0:0 0:0 1:0");  // no value in the epoch: the memory is unchanged
    const auto events = site.db->alarms().events(std::nullopt);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, "shelve_expired");
    EXPECT_EQ(events[0].time, 2000);
    EXPECT_EQ(events[0].actor, "rule");
}

}  // namespace
}  // namespace tlsmon::test
