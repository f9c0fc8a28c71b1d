// The alarm rules evaluated inside an epoch's commit on a real SQLite file: a step series
// raises within on-delay + 1 epochs and none before, states survive a reopen, a backlog is
// evaluated in acquisition order, rate rules read the stored series, rejected and degraded
// epochs are not evaluated; rules on a campaign quantity step on stored campaigns only.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pipeline/alarm_evaluation.hpp"
#include "storage/campaign_store.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;
constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z
constexpr const char* kZone = "pier P3 top";
constexpr const char* kQuantity = "m3c2_median_m";

std::string sha(int n) {
    std::string s(64, '0');
    const auto d = std::to_string(n);
    s.replace(64 - d.size(), d.size(), d);
    return s;
}

AlarmRuleSpec settlement_rule() {
    AlarmRuleSpec r;
    r.name = "P3 settlement";
    r.zone = kZone;
    r.quantity = kQuantity;
    r.levels[0] = LevelLimits{0.005, std::nullopt, 0.001};
    r.levels[2] = LevelLimits{0.010, std::nullopt, 0.002};
    r.on_delay = 2;
    return r;
}

struct Site {
    test::TempDir dir;
    std::optional<EpochDatabase> db = open();
    std::vector<AlarmRuleSpec> rules{settlement_rule()};
    int n = 0;

    EpochDatabase open() { return EpochDatabase::open(dir / "e.sqlite", Mode::read_write); }
    Site() {
        db->site().upsert_zone(kZone, "{}");
        store_alarm_rules(*db, rules);
    }
    Epoch insert(UtcSeconds t) {
        const auto id = db->epochs().insert({sha(++n), t, "/ingest/s.ptx", 10, std::nullopt}).id;
        return *db->epochs().find(id);
    }
    void commit(const Epoch& e, EpochResults r) {
        ASSERT_TRUE(db->epochs().claim(e.id));
        db->results().commit(e.id, r, [&](const AlarmStore& a, const SeriesReader& s) {
            return evaluate_epoch_alarms(rules, e, r, a, s);
        });
    }
    // One accepted epoch with the zone's value.
    Epoch add(UtcSeconds t, double value, bool significant = true) {
        const Epoch e = insert(t);
        EpochResults r;
        r.zone_results = {{kZone, kQuantity, value, 0.001, 100, significant}};
        commit(e, r);
        return e;
    }
    AlarmState state(const std::string& rule = "P3 settlement") const {
        for (const auto& s : db->alarms().states()) {
            if (s.rule == rule) return s;
        }
        return AlarmState{rule, "normal", "", 0, {}, {}, "", {}, "", {}};
    }
};

TEST(AlarmEvaluation, StepRaisesWithinOnDelayPlusOneEpochsAndNoneBefore) {
    Site site;
    std::vector<EpochId> ids;
    for (int k = 0; k < 8; ++k) {
        // 0 mm, then a 12 mm step at epoch 3: above the alarm level (10 mm).
        ids.push_back(site.add(kT0 + 900 * k, k < 3 ? 0.0 : 0.012).id);
        if (k < 5) {
            EXPECT_EQ(site.state().state, "normal") << "epoch " << k;
        }
    }
    const auto s = site.state();
    EXPECT_EQ(s.state, "unack");
    EXPECT_EQ(s.level, "alarm");
    const auto events = site.db->alarms().events(std::nullopt);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, "raise");
    EXPECT_EQ(events[0].time, kT0 + 900 * 5);  // epoch 3 + on_delay 2
    EXPECT_EQ(events[0].epoch, ids[5]);
    EXPECT_DOUBLE_EQ(*events[0].value, 0.012);
    EXPECT_EQ(events[0].level, "alarm");
    EXPECT_EQ(events[0].actor, "rule");
    EXPECT_EQ(events[0].message, "normal -> unack");
}

TEST(AlarmEvaluation, StateAndDelayCountsSurviveAReopen) {
    Site site;
    site.add(kT0, 0.012);
    site.add(kT0 + 900, 0.012);  // 2 of the 3 epochs the on-delay needs
    site.db.reset();
    site.db.emplace(site.open());
    EXPECT_EQ(site.state().memory, "0:2 0:0 0:2");
    site.add(kT0 + 1800, 0.012);
    EXPECT_EQ(site.state().state, "unack");
    site.db.reset();
    site.db.emplace(site.open());
    const auto s = site.state();
    EXPECT_EQ(s.state, "unack");
    EXPECT_EQ(s.level, "alarm");
    EXPECT_EQ(s.evaluated, kT0 + 1800);
}

TEST(AlarmEvaluation, BacklogIsEvaluatedInAcquisitionOrder) {
    Site site;
    site.rules[0].on_delay = 0;
    // Three scans arrive in the order 3, 1, 2; the pipeline takes pending epochs by
    // acquisition time (Epochs::pending), so the rule sees 1, 2, 3.
    const std::map<UtcSeconds, double> values{{kT0, 0.0}, {kT0 + 900, 0.012}, {kT0 + 1800, 0.0}};
    for (UtcSeconds t : {kT0 + 1800, kT0, kT0 + 900}) site.insert(t);
    for (const auto& e : site.db->epochs().pending()) {
        EpochResults r;
        r.zone_results = {{kZone, kQuantity, values.at(e.acquired), 0.001, 100, true}};
        site.commit(e, r);
    }
    const auto events = site.db->alarms().events(std::nullopt);
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].kind, "raise");
    EXPECT_EQ(events[0].time, kT0 + 900);
    EXPECT_EQ(events[1].kind, "return");
    EXPECT_EQ(events[1].time, kT0 + 1800);
    EXPECT_EQ(site.state().state, "rtn_unack");
    // A scan acquired before the newest evaluated one leaves the rule untouched.
    const Epoch late = site.insert(kT0 + 450);
    EpochResults r;
    r.zone_results = {{kZone, kQuantity, 0.05, 0.001, 100, true}};
    site.commit(late, r);
    EXPECT_EQ(site.state().state, "rtn_unack");
    EXPECT_EQ(site.db->alarms().events(std::nullopt).size(), 2u);
    // ... but never silently: a system event names the rule, the epoch and both times.
    const auto said = site.db->series().events({}, std::string("alarm_rule_late_epoch"));
    ASSERT_EQ(said.size(), 1u);
    EXPECT_EQ(said[0].epoch, late.id);
    EXPECT_NE(said[0].message.find("rule P3 settlement: epoch " + std::to_string(late.id) +
                                   " was acquired 2026-03-01T12:07:30Z, before the newest epoch "
                                   "the rule evaluated (2026-03-01T12:30:00Z)"),
              std::string::npos)
        << said[0].message;
}

// An epoch that no registration took to the reference's frame (no targets, no ICP): its
// values carry the scanner's own movement and raise nothing, unless the rule says so.
TEST(AlarmEvaluation, UnregisteredEpochsRaiseOnlyWhereTheRuleTakesThem) {
    Site site;
    site.rules[0].on_delay = 0;
    AlarmRuleSpec taking = settlement_rule();
    taking.name = "P3 settlement, scanner on rock";
    taking.on_delay = 0;
    taking.evaluate_unregistered = true;
    site.rules.push_back(taking);
    store_alarm_rules(*site.db, site.rules);
    const Epoch e = site.insert(kT0);
    EpochResults r;
    r.registration = RegistrationRow{};
    r.registration->method = kUnregistered;
    r.registration->accepted = false;
    r.zone_results = {{kZone, kQuantity, 0.02, 0.001, 100, true}};
    site.commit(e, r);
    EXPECT_EQ(site.state().state, "normal");
    EXPECT_EQ(site.state("P3 settlement, scanner on rock").state, "unack");
}

TEST(AlarmEvaluation, RejectedAndDegradedEpochsAndInsignificantValuesDoNotRaise) {
    Site site;
    site.rules[0].on_delay = 0;
    site.rules[0].significant_only = true;
    site.add(kT0, 0.02, false);  // below its LoD
    EXPECT_EQ(site.state().state, "normal");
    const Epoch degraded = site.insert(kT0 + 900);
    EpochResults r;
    r.registration = RegistrationRow{};
    r.registration->accepted = false;
    r.zone_results = {{kZone, kQuantity, 0.02, 0.001, 100, true}};
    site.commit(degraded, r);
    EXPECT_EQ(site.state().state, "normal");
    const Epoch rejected = site.insert(kT0 + 1800);
    EpochResults rej;
    rej.outcome = EpochStatus::rejected;
    rej.reason = "2 of 4 targets unstable";
    site.commit(rejected, rej);
    EXPECT_EQ(site.state().state, "normal");
    EXPECT_TRUE(site.db->alarms().events(std::nullopt).empty());
    site.add(kT0 + 2700, 0.02, true);
    EXPECT_EQ(site.state().state, "unack");
}

TEST(AlarmEvaluation, AnEpochAcceptedWithAScaledCovarianceRaises) {
    // A failed global test within its hard limit: the registration is accepted with its
    // covariance scaled by s0² (docs/registration.md, "Global test policy"). Its values are
    // sound, so the rule sees them as any accepted epoch's.
    Site site;
    site.rules[0].on_delay = 0;
    site.add(kT0, 0.0);
    const Epoch scaled = site.insert(kT0 + 900);
    EpochResults r;
    r.registration = RegistrationRow{};
    r.registration->accepted = true;
    r.registration->status = "accepted_scaled";
    r.registration->variance_factor = 2.1;
    r.zone_results = {{kZone, kQuantity, 0.02, 0.001, 100, true}};
    site.commit(scaled, r);
    EXPECT_EQ(site.state().state, "unack");
}

TEST(AlarmEvaluation, RateRuleReadsTheStoredSeries) {
    Site site;
    AlarmRuleSpec rate;
    rate.name = "P3 settlement rate";
    rate.zone = kZone;
    rate.quantity = kQuantity;
    rate.levels[1] = LevelLimits{2.0, std::nullopt, 0.5};  // alert above 2 mm/day
    rate.rate_window_seconds = 6 * 3600;
    site.rules = {rate};
    store_alarm_rules(*site.db, site.rules);
    // 3 mm/day for 4 hours, every 15 min: rate 3 mm/day from the second epoch on.
    for (int k = 0; k <= 16; ++k) {
        site.add(kT0 + 900 * k, 0.003 * 900.0 * k / 86400.0);
        if (k == 0) {
            EXPECT_EQ(site.state(rate.name).state, "normal");
        }
    }
    const auto s = site.state(rate.name);
    EXPECT_EQ(s.state, "unack");
    EXPECT_EQ(s.level, "alert");
    EXPECT_NEAR(*s.value, 3.0, 1e-9);
    const auto events = site.db->alarms().events(std::nullopt, rate.name);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].time, kT0 + 900);
}

// A stored campaign with one zone value, its rules evaluated inside its transaction.
CampaignId add_campaign_value(Site& site, UtcSeconds t, double value, bool significant = true) {
    CampaignRow c;
    c.sha256 = sha(1000 + ++site.n);
    c.instrument = "backpack";
    c.kind = "pls";
    c.file_path = "/archive/pls.ply";
    c.acquired = t;
    c.added = t;
    c.reference_epoch = 1;  // the station's first epoch (added before)
    c.parameters_json = "{}";
    const std::vector<ZoneResult> zones{
        {kZone, kCampaignC2cMedian, value, 0.004, 300, significant}};
    return site.db->campaigns().add(
        c, {}, {}, zones, [&](CampaignId id, const AlarmStore& a, const SeriesReader& s) {
            return evaluate_campaign_alarms(site.rules, id, t, zones, a, s);
        });
}

TEST(AlarmEvaluation, CampaignRulesStepOnCampaignsAndStationRulesOnEpochsOnly) {
    Site site;
    AlarmRuleSpec bulge;
    bulge.name = "P3 bulge";
    bulge.zone = kZone;
    bulge.quantity = kCampaignC2cMedian;
    bulge.levels[2] = LevelLimits{0.015, std::nullopt, 0.002};
    AlarmRuleSpec bulge_rate = bulge;
    bulge_rate.name = "P3 bulge rate";
    bulge_rate.levels[2] = LevelLimits{5.0, std::nullopt, 0.5};  // mm/day
    bulge_rate.rate_window_seconds = 3 * 86400;
    site.rules = {settlement_rule(), bulge, bulge_rate};
    store_alarm_rules(*site.db, site.rules);

    // Station epochs far above the campaign rule's level: only the station's rule moves.
    for (int k = 0; k < 4; ++k) site.add(kT0 + 900 * k, 0.030);
    EXPECT_EQ(site.state().state, "unack");
    EXPECT_EQ(site.state("P3 bulge").state, "normal");
    EXPECT_FALSE(site.state("P3 bulge").evaluated);

    // A campaign inside the level, then one a day later above it: raised at its time, with
    // no epoch and the campaign named; the rate over the two is 20 mm/day.
    add_campaign_value(site, kT0 + 3600, 0.002);
    EXPECT_EQ(site.state("P3 bulge").state, "normal");
    const CampaignId second = add_campaign_value(site, kT0 + 3600 + 86400, 0.022);
    const auto s = site.state("P3 bulge");
    EXPECT_EQ(s.state, "unack");
    EXPECT_EQ(s.level, "alarm");
    EXPECT_EQ(*s.value, 0.022);
    EXPECT_FALSE(s.epoch);
    const auto events = site.db->alarms().events(std::nullopt, "P3 bulge");
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].time, kT0 + 3600 + 86400);
    EXPECT_NE(events[0].message.find("(campaign " + std::to_string(second) + ")"),
              std::string::npos)
        << events[0].message;
    const auto rate = site.state("P3 bulge rate");
    EXPECT_EQ(rate.state, "unack");
    EXPECT_NEAR(*rate.value, 20.0, 1e-9);
    // The station's rule kept the state the epochs gave it.
    EXPECT_EQ(site.state().state, "unack");
    EXPECT_EQ(site.db->alarms().events(std::nullopt, "P3 settlement").size(), 1u);

    // A campaign acquired before the newest one the rule took: stored, not stepped back to,
    // said in an event.
    add_campaign_value(site, kT0 + 7200, 0.0);
    EXPECT_EQ(site.state("P3 bulge").state, "unack");
    EXPECT_EQ(site.db->series().points(kZone, kCampaignC2cMedian, {}).size(), 3u);
    bool said = false;
    for (const auto& e : site.db->series().events({}, std::string("alarm_rule_late_epoch")))
        said = said || e.message.find("campaign") != std::string::npos;
    EXPECT_TRUE(said);
}

}  // namespace
}  // namespace tlsmon
