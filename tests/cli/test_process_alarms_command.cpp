// `tlsmon alarms`, `tlsmon alarms history` and `tlsmon alarms ack|shelve|unshelve` on the
// SQLite file of a real daemon: an unacknowledged alarm survives daemon restarts, the CLI
// acknowledges it (event by "CLI"), shelving suppresses it and unshelving annunciates the
// standing alarm afresh.
#include <gtest/gtest.h>
#include <pwd.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "pipeline/alarm_evaluation.hpp"
#include "tests/support/daemon_harness.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z
const std::string kRules =
    "[[zone]]\nname = \"pier P3 top\"\nmin = [0, 0, 0]\nmax = [1, 1, 10]\n"
    "[[alarm.rule]]\nname = \"P3 settlement\"\nzone = \"pier P3 top\"\n"
    "quantity = \"m3c2_median_m\"\nalarm = { high = 0.010, deadband = 0.002 }\n";

std::string tlsmon(const std::string& args) {
    return std::string(TLSMON_BINARY) + " " + args;
}

// An epoch whose zone value (12 mm) is above the alarm level, committed with the rules of
// the site's configuration, as the pipeline commits it.
void commit_step_epoch(const test::Site& site) {
    const Config config = load_config(site.config());
    auto db = EpochDatabase::open(site.database(), EpochDatabase::Mode::read_write);
    const auto id =
        db.epochs().insert({std::string(64, 'b'), kT0, "/ingest/s.ptx", 10, std::nullopt}).id;
    ASSERT_TRUE(db.epochs().claim(id));
    const Epoch epoch = *db.epochs().find(id);
    EpochResults r;
    r.zone_results = {{"pier P3 top", "m3c2_median_m", 0.012, 0.001, 100, true}};
    db.results().commit(id, r, [&](const AlarmStore& a, const SeriesReader& s) {
        return evaluate_epoch_alarms(config.alarm.rules, epoch, r, a, s);
    });
}

AlarmState state_of(const test::Site& site, const std::string& rule = "P3 settlement") {
    for (const auto& s : site.open_db().alarms().states()) {
        if (s.rule == rule) return s;
    }
    return AlarmState{rule, "(no row)", "", 0, {}, {}, "", {}, "", {}};
}

TEST(AlarmsCommand, UnackSurvivesRestartsAndTheCliAcknowledgesShelvesAndUnshelves) {
    test::Site site("alarms", kRules);
    const std::string once = tlsmon("run --once --config " + site.config().string());
    ASSERT_EQ(test::shell(once).status, 0);
    commit_step_epoch(site);
    EXPECT_EQ(state_of(site).state, "unack");

    // A restart of the daemon keeps the state, its level and the rule's memory.
    const auto again = test::shell(once);
    ASSERT_EQ(again.status, 0) << again.output;
    const auto kept = state_of(site);
    EXPECT_EQ(kept.state, "unack");
    EXPECT_EQ(kept.level, "alarm");
    EXPECT_EQ(kept.memory, "0:0 0:0 1:0");
    EXPECT_EQ(kept.evaluated, kT0);
    // The newest epoch was acquired on 2026-03-01, more than 3 x 15 min ago: stale.
    const auto stale = state_of(site, "system.stale");
    EXPECT_EQ(stale.state, "unack");
    EXPECT_EQ(stale.level, "alarm");

    const std::string db = " --db " + site.database().string();
    auto listed = test::shell(tlsmon("alarms --format csv" + db));
    ASSERT_EQ(listed.status, 0) << listed.output;
    EXPECT_NE(listed.output.find("P3 settlement,unack,alarm,2026-03-01T12:00:00Z,0.012,1,"),
              std::string::npos)
        << listed.output;
    EXPECT_NE(listed.output.find("system.stale,unack,alarm,"), std::string::npos) << listed.output;

    auto ack = test::shell(tlsmon("alarms ack 'P3 settlement' --config " + site.config().string()));
    ASSERT_EQ(ack.status, 0) << ack.output;
    EXPECT_EQ(ack.output, "ack: 1 rule changed\n");
    EXPECT_EQ(state_of(site).state, "ack");
    // Every rule: only system.stale is left to acknowledge; then nothing.
    EXPECT_EQ(test::shell(tlsmon("alarms ack '*'" + db)).output, "ack: 1 rule changed\n");
    EXPECT_EQ(state_of(site, "system.stale").state, "ack");
    EXPECT_EQ(test::shell(tlsmon("alarms ack '*'" + db)).output, "ack: 0 rules changed\n");

    // A shelve is temporary: at most 30 days ahead (docs/alarms.md).
    const auto far = test::shell(tlsmon("alarms shelve 'P3 settlement' --until 2099-01-01" + db));
    EXPECT_EQ(far.status, 1);
    EXPECT_NE(far.output.find("a shelve lasts at most 30 days"), std::string::npos) << far.output;
    EXPECT_EQ(state_of(site).state, "ack") << "a refused shelve changes nothing";
    const UtcSeconds in_a_week = now_utc() + 7 * 86400;
    ASSERT_EQ(
        test::shell(tlsmon("alarms shelve 'P3 settlement' --until " + format_utc(in_a_week) + db))
            .status,
        0);
    const auto shelved = state_of(site);
    EXPECT_EQ(shelved.state, "shelved");
    EXPECT_EQ(shelved.shelved_until, in_a_week);
    ASSERT_EQ(test::shell(tlsmon("alarms unshelve 'P3 settlement'" + db)).status, 0);
    EXPECT_EQ(state_of(site).state, "unack");  // the condition still stands: annunciated afresh

    const auto history =
        test::shell(tlsmon("alarms history --rule 'P3 settlement' --format json" + db));
    ASSERT_EQ(history.status, 0) << history.output;
    const auto events = nlohmann::json::parse(history.output);
    ASSERT_EQ(events.size(), 4u) << history.output;
    EXPECT_EQ(events[0]["kind"], "raise");
    EXPECT_EQ(events[0]["actor"], "rule");
    EXPECT_EQ(events[0]["time"], "2026-03-01T12:00:00Z");
    // The raise carries its epoch's acquisition time, the operator's ack the system clock.
    EXPECT_EQ(events[0]["time_base"], "acquisition");
    EXPECT_EQ(events[1]["time_base"], "system");
    EXPECT_EQ(events[1]["kind"], "ack");
    const std::string user = "user " + std::string(::getpwuid(::getuid())->pw_name);
    EXPECT_EQ(events[1]["actor"], "CLI " + user);
    EXPECT_EQ(events[1]["message"], "unack -> ack by CLI (" + user + ")");
    EXPECT_EQ(events[2]["kind"], "shelve");
    EXPECT_EQ(events[3]["kind"], "unshelve");
}

// The running daemon ends a shelve at its expiry (every daemon.status_interval), without an
// epoch; out of service holds until `in-service`.
TEST(AlarmsCommand, DaemonEndsAShelveAtItsExpiryAndOutOfServiceHolds) {
    test::Site site("alarms-expiry", kRules + "[daemon]\nstatus_interval = 1\n");
    ASSERT_EQ(test::shell(tlsmon("run --once --config " + site.config().string())).status, 0);
    commit_step_epoch(site);
    const std::string db = " --db " + site.database().string();
    ASSERT_EQ(test::shell(tlsmon("alarms out-of-service 'system.stale'" + db)).output,
              "out-of-service: 1 rule changed\n");
    const UtcSeconds until = now_utc() + 3;
    ASSERT_EQ(test::shell(tlsmon("alarms shelve 'P3 settlement' --until " + format_utc(until) + db))
                  .status,
              0);
    EXPECT_EQ(state_of(site).state, "shelved");

    test::DaemonProcess daemon(site.config(), site.log());
    EXPECT_TRUE(test::wait_until([&] { return state_of(site).state != "shelved"; }, 15))
        << "the shelve did not expire";
    const UtcSeconds noticed = now_utc();
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(10), 0);
    const auto expired = state_of(site);
    EXPECT_EQ(expired.state, "unack");  // the 12 mm condition still stands
    EXPECT_GE(expired.since, until);
    EXPECT_LE(noticed, until + 3);  // within the status interval (1 s) and the poll
    const auto history =
        test::shell(tlsmon("alarms history --format csv --rule 'P3 settlement'" + db));
    EXPECT_NE(history.output.find(",shelve_expired,"), std::string::npos) << history.output;
    // The stale alarm stood while out of service but was not annunciated; in service: it is.
    EXPECT_EQ(state_of(site, "system.stale").state, "out_of_service");
    ASSERT_EQ(test::shell(tlsmon("alarms in-service 'system.stale'" + db)).status, 0);
    EXPECT_EQ(state_of(site, "system.stale").state, "unack");
}

TEST(AlarmsCommand, UnknownRuleAndPastShelveAreErrorsNamingThem) {
    test::Site site("alarms-errors", kRules);
    ASSERT_EQ(test::shell(tlsmon("run --once --config " + site.config().string())).status, 0);
    const std::string db = " --db " + site.database().string();
    const auto unknown = test::shell(tlsmon("alarms ack 'P4 tilt'" + db));
    EXPECT_EQ(unknown.status, 1);
    EXPECT_NE(unknown.output.find("no alarm rule 'P4 tilt'"), std::string::npos) << unknown.output;
    EXPECT_NE(unknown.output.find(
                  "(rules: P3 settlement, system.central_forward, system.database_error,"),
              std::string::npos)
        << unknown.output;
    const auto past = test::shell(tlsmon("alarms shelve 'P3 settlement' --until 2020-01-01" + db));
    EXPECT_EQ(past.status, 1);
    EXPECT_NE(past.output.find("a shelve ends in the future"), std::string::npos) << past.output;
}

}  // namespace
}  // namespace tlsmon
