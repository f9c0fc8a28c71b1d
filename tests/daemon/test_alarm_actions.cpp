// acknowledge_alarm (the contract shared with the Modbus server) and shelving, on a real
// SQLite file: ISA-18.2 unack -> ack, rtn_unack -> normal, others unchanged; one event per
// rule changed, naming the actor.
#include <gtest/gtest.h>

#include "daemon/alarm_actions.hpp"
#include "daemon/alarm_shelving.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

struct Fixture {
    test::TempDir dir;
    EpochDatabase db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
    Fixture() {
        db.site().upsert_zone("z", "{}");
        for (const char* name : {"a", "b", "c", "d"}) {
            db.alarms().upsert_rule({0, name, "z", "m3c2_median_m", "{}", true});
        }
        // a: unack (alarm), b: rtn_unack (warning), c: ack, d: no state row (normal).
        db.alarms().set_state(
            {"a", "unack", "alarm", 100, 0.012, std::nullopt, "alarm", std::nullopt, "", 100});
        db.alarms().set_state(
            {"b", "rtn_unack", "warning", 100, 0.001, std::nullopt, "", std::nullopt, "", 100});
        db.alarms().set_state(
            {"c", "ack", "alert", 100, 0.009, std::nullopt, "alert", std::nullopt, "", 100});
    }
    std::string state(const std::string& rule) const {
        for (const auto& s : db.alarms().states()) {
            if (s.rule == rule) return s.state;
        }
        return "(none)";
    }
};

TEST(AlarmActions, AcknowledgeOneRuleBySCADA) {
    Fixture f;
    EXPECT_EQ(acknowledge_alarm(f.db, "a", AlarmActor::scada, 200), 1);
    EXPECT_EQ(f.state("a"), "ack");
    const auto events = f.db.alarms().events(std::nullopt);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].rule, "a");
    EXPECT_EQ(events[0].kind, "ack");
    EXPECT_EQ(events[0].actor, "SCADA");
    EXPECT_EQ(events[0].time, 200);
    EXPECT_EQ(events[0].level, "alarm");
    EXPECT_DOUBLE_EQ(events[0].value.value(), 0.012);
    EXPECT_EQ(acknowledge_alarm(f.db, "c", AlarmActor::scada, 210), 0);  // already ack
    EXPECT_EQ(f.db.alarms().events(std::nullopt).size(), 1u);
}

TEST(AlarmActions, AcknowledgeEveryRule) {
    Fixture f;
    EXPECT_EQ(acknowledge_alarm(f.db, "*", AlarmActor::cli, 300), 2);  // a and b
    EXPECT_EQ(f.state("a"), "ack");
    EXPECT_EQ(f.state("b"), "normal");
    EXPECT_EQ(f.state("c"), "ack");
    EXPECT_EQ(f.state("d"), "(none)");
    for (const auto& e : f.db.alarms().events(std::nullopt)) EXPECT_EQ(e.actor, "CLI");
}

TEST(AlarmActions, UnknownRuleNamesTheRules) {
    Fixture f;
    try {
        acknowledge_alarm(f.db, "x", AlarmActor::cli, 1);
        FAIL() << "an unknown rule was acknowledged";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("(rules: a, b, c, d)"), std::string::npos) << e.what();
    }
}

TEST(AlarmActions, ShelveAndUnshelve) {
    Fixture f;
    EXPECT_EQ(shelve_alarm(f.db, "c", 1000, AlarmActor::cli, 500), 1);
    EXPECT_EQ(f.state("c"), "shelved");
    EXPECT_EQ(acknowledge_alarm(f.db, "c", AlarmActor::cli, 600), 0);
    EXPECT_EQ(unshelve_alarm(f.db, "c", AlarmActor::cli, 700), 1);
    EXPECT_EQ(f.state("c"), "unack");  // its condition (alert) still stands
    EXPECT_EQ(unshelve_alarm(f.db, "c", AlarmActor::cli, 800), 0);
    // A shelve whose expiry has passed ends at the next action on the rule.
    EXPECT_EQ(shelve_alarm(f.db, "d", 900, AlarmActor::cli, 800), 1);
    EXPECT_EQ(acknowledge_alarm(f.db, "d", AlarmActor::cli, 950), 1);
    EXPECT_EQ(f.state("d"), "normal");
    EXPECT_EQ(f.db.alarms().events(std::nullopt).back().kind, "shelve_expired");
}

TEST(AlarmActions, DueShelvesExpireWithoutAnEpoch) {
    Fixture f;
    ASSERT_EQ(shelve_alarm(f.db, "a", 1000, AlarmActor::cli, 500), 1);
    ASSERT_EQ(shelve_alarm(f.db, "d", 2000, AlarmActor::cli, 500), 1);
    EXPECT_EQ(expire_due_shelves(f.db, 999), 0);
    EXPECT_EQ(f.state("a"), "shelved");
    EXPECT_EQ(expire_due_shelves(f.db, 1000), 1);  // a's expiry reached, d's not
    EXPECT_EQ(f.state("a"), "unack");              // its condition (alarm) still stands
    EXPECT_EQ(f.state("d"), "shelved");
    const auto last = f.db.alarms().events(std::nullopt).back();
    EXPECT_EQ(last.rule, "a");
    EXPECT_EQ(last.kind, "shelve_expired");
    EXPECT_EQ(last.actor, "rule");
    EXPECT_EQ(last.time, 1000);
    EXPECT_EQ(expire_due_shelves(f.db, 2500), 1);
    EXPECT_EQ(f.state("d"), "normal");  // no condition: back to normal
    EXPECT_EQ(expire_due_shelves(f.db, 3000), 0);
}

TEST(AlarmActions, OutOfServiceUntilReturnedNotByTime) {
    Fixture f;
    EXPECT_EQ(remove_alarm_from_service(f.db, "a", AlarmActor::cli, 100), 1);
    EXPECT_EQ(f.state("a"), "out_of_service");
    EXPECT_EQ(remove_alarm_from_service(f.db, "a", AlarmActor::cli, 110), 0);  // already
    EXPECT_EQ(acknowledge_alarm(f.db, "a", AlarmActor::cli, 120), 0);
    EXPECT_THROW(shelve_alarm(f.db, "a", 900, AlarmActor::cli, 130), Error);
    EXPECT_EQ(expire_due_shelves(f.db, 1'000'000), 0);  // no expiry
    EXPECT_EQ(f.state("a"), "out_of_service");
    EXPECT_EQ(return_alarm_to_service(f.db, "a", AlarmActor::cli, 200), 1);
    EXPECT_EQ(f.state("a"), "unack");  // its condition still stands: annunciated afresh
    EXPECT_EQ(return_alarm_to_service(f.db, "a", AlarmActor::cli, 210), 0);
    EXPECT_EQ(remove_alarm_from_service(f.db, "d", AlarmActor::cli, 300), 1);
    EXPECT_EQ(return_alarm_to_service(f.db, "d", AlarmActor::cli, 310), 1);
    EXPECT_EQ(f.state("d"), "normal");
    std::vector<std::string> kinds;
    for (const auto& e : f.db.alarms().events(std::nullopt)) {
        EXPECT_EQ(e.actor, "CLI");
        kinds.push_back(e.kind);
    }
    EXPECT_EQ(kinds, (std::vector<std::string>{"out_of_service", "in_service", "out_of_service",
                                               "in_service"}));
}

}  // namespace
}  // namespace tlsmon
