// Every transition of the ISA-18.2 state machine (fig. 5), with levels, latching, shelving
// and out of service.
#include <gtest/gtest.h>

#include "alarms/alarm_machine.hpp"
#include "core/error.hpp"

namespace tlsmon {
namespace {

using L = AlarmLevel;
using S = IsaState;
constexpr auto kRule = AlarmActorKind::rule;
constexpr auto kCli = AlarmActorKind::cli;

AlarmMachineState in(S s, L level, L process) {
    return {s, level, process, 0, std::nullopt};
}

TEST(AlarmMachine, NormalRaisesToUnackAtTheProcessLevel) {
    const auto step = on_process({}, L::alert, false, 100);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::alert);
    EXPECT_EQ(step.state.since, 100);
    ASSERT_EQ(step.events.size(), 1u);
    EXPECT_EQ(step.events[0].kind, "raise");
    EXPECT_EQ(step.events[0].from, S::normal);
    EXPECT_EQ(step.events[0].to, S::unack);
    EXPECT_EQ(step.events[0].actor, kRule);
    EXPECT_EQ(step.events[0].time, 100);
}

TEST(AlarmMachine, NormalStaysNormalWithoutEvents) {
    const auto step = on_process({}, L::none, false, 100);
    EXPECT_EQ(step.state.state, S::normal);
    EXPECT_TRUE(step.events.empty());
}

TEST(AlarmMachine, UnackToAckByAcknowledge) {
    const auto step = on_acknowledge(in(S::unack, L::alarm, L::alarm), kCli, 50);
    EXPECT_EQ(step.state.state, S::ack);
    EXPECT_EQ(step.state.level, L::alarm);
    ASSERT_EQ(step.events.size(), 1u);
    EXPECT_EQ(step.events[0].kind, "ack");
    EXPECT_EQ(step.events[0].actor, kCli);
}

TEST(AlarmMachine, UnackReturnsToRtnUnack) {
    const auto step = on_process(in(S::unack, L::warning, L::warning), L::none, false, 10);
    EXPECT_EQ(step.state.state, S::rtn_unack);
    EXPECT_EQ(step.state.level, L::warning);  // the level that was annunciated
    ASSERT_EQ(step.events.size(), 1u);
    EXPECT_EQ(step.events[0].kind, "return");
}

TEST(AlarmMachine, RtnUnackToNormalByAcknowledge) {
    const auto step = on_acknowledge(in(S::rtn_unack, L::warning, L::none), kCli, 10);
    EXPECT_EQ(step.state.state, S::normal);
    EXPECT_EQ(step.state.level, L::none);
}

TEST(AlarmMachine, RtnUnackRaisesAgainToUnack) {
    const auto step = on_process(in(S::rtn_unack, L::warning, L::none), L::alert, false, 10);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::alert);
    EXPECT_EQ(step.events.at(0).kind, "raise");
}

TEST(AlarmMachine, AckClearsToNormalWhenTheProcessReturns) {
    const auto step = on_process(in(S::ack, L::alert, L::alert), L::none, false, 10);
    EXPECT_EQ(step.state.state, S::normal);
    EXPECT_EQ(step.state.level, L::none);
    EXPECT_EQ(step.events.at(0).kind, "clear");
}

TEST(AlarmMachine, HigherLevelWhileAcknowledgedIsANewUnacknowledgedAlarm) {
    const auto step = on_process(in(S::ack, L::warning, L::warning), L::alarm, false, 10);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::alarm);
    EXPECT_EQ(step.events.at(0).kind, "escalate");
}

TEST(AlarmMachine, LowerLevelKeepsTheAcknowledgement) {
    const auto step = on_process(in(S::ack, L::alarm, L::alarm), L::warning, false, 10);
    EXPECT_EQ(step.state.state, S::ack);
    EXPECT_EQ(step.state.level, L::warning);
    EXPECT_EQ(step.events.at(0).kind, "deescalate");
}

TEST(AlarmMachine, EscalationWhileUnacknowledgedStaysUnack) {
    const auto up = on_process(in(S::unack, L::warning, L::warning), L::alarm, false, 10);
    EXPECT_EQ(up.state.state, S::unack);
    EXPECT_EQ(up.state.level, L::alarm);
    EXPECT_EQ(up.events.at(0).kind, "escalate");
    const auto same = on_process(up.state, L::alarm, false, 20);
    EXPECT_TRUE(same.events.empty());
}

TEST(AlarmMachine, AcknowledgeInNormalOrAckChangesNothing) {
    EXPECT_TRUE(on_acknowledge({}, kCli, 1).events.empty());
    const auto step = on_acknowledge(in(S::ack, L::alert, L::alert), kCli, 1);
    EXPECT_EQ(step.state.state, S::ack);
    EXPECT_TRUE(step.events.empty());
}

TEST(AlarmMachine, LatchedAlarmStaysUntilAcknowledged) {
    // unack, process returns: latched stays unack; the acknowledgement resets to normal.
    auto step = on_process(in(S::unack, L::alarm, L::alarm), L::none, true, 10);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::alarm);
    step = on_acknowledge(step.state, kCli, 20);
    EXPECT_EQ(step.state.state, S::normal);
    // ack, process returns: latched stays ack until reset by acknowledgement.
    step = on_process(in(S::ack, L::alert, L::alert), L::none, true, 30);
    EXPECT_EQ(step.state.state, S::ack);
    EXPECT_EQ(step.state.level, L::alert);
    step = on_acknowledge(step.state, kCli, 40);
    EXPECT_EQ(step.state.state, S::normal);
    EXPECT_EQ(step.events.at(0).kind, "reset");
}

TEST(AlarmMachine, LatchedAlarmStillActiveAcknowledgesToAck) {
    const auto step = on_acknowledge(in(S::unack, L::alarm, L::alarm), kCli, 10);
    EXPECT_EQ(step.state.state, S::ack);
}

TEST(AlarmMachine, ShelvedSuppressesAndExpiresIntoTheStandingCondition) {
    auto step = on_shelve(in(S::unack, L::alert, L::alert), 1000, kCli, 100);
    EXPECT_EQ(step.state.state, S::shelved);
    EXPECT_EQ(step.state.shelved_until, 1000);
    EXPECT_EQ(step.events.at(0).kind, "shelve");
    // The process goes normal and abnormal again while shelved: no annunciation.
    step = on_process(step.state, L::none, false, 200);
    EXPECT_EQ(step.state.state, S::shelved);
    EXPECT_TRUE(step.events.empty());
    step = on_process(step.state, L::alarm, false, 999);
    EXPECT_EQ(step.state.state, S::shelved);
    EXPECT_TRUE(step.events.empty());
    // At the expiry (1000 <= now) the standing alarm is annunciated afresh.
    step = on_process(step.state, L::alarm, false, 1000);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::alarm);
    ASSERT_EQ(step.events.size(), 1u);
    EXPECT_EQ(step.events[0].kind, "shelve_expired");
    EXPECT_FALSE(step.state.shelved_until);
}

TEST(AlarmMachine, ShelveExpiresToNormalWhenTheProcessIsNormal) {
    auto step = on_shelve(in(S::ack, L::warning, L::warning), 500, kCli, 100);
    step = on_process(step.state, L::none, false, 400);
    EXPECT_EQ(step.state.state, S::shelved);
    step = expire_shelve(step.state, 499);
    EXPECT_EQ(step.state.state, S::shelved);
    step = expire_shelve(step.state, 500);
    EXPECT_EQ(step.state.state, S::normal);
}

TEST(AlarmMachine, UnshelveBeforeExpiry) {
    auto step = on_shelve(in(S::normal, L::none, L::none), 5000, kCli, 100);
    step = on_process(step.state, L::warning, false, 200);
    step = on_unshelve(step.state, kCli, 300);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::warning);
    EXPECT_EQ(step.events.at(0).kind, "unshelve");
    EXPECT_EQ(step.events.at(0).actor, kCli);
    // Unshelving what is not shelved changes nothing.
    EXPECT_TRUE(on_unshelve(step.state, kCli, 400).events.empty());
}

TEST(AlarmMachine, ShelveMustEndInTheFuture) {
    EXPECT_THROW(on_shelve({}, 100, kCli, 100), Error);
}

TEST(AlarmMachine, ShelveIsTemporary) {
    const UtcSeconds now = 1'800'000'000;
    EXPECT_EQ(on_shelve({}, now + kMaxShelveSeconds, kCli, now).state.state, S::shelved);
    try {
        on_shelve({}, now + kMaxShelveSeconds + 1, kCli, now);
        ADD_FAILURE() << "a shelve past 30 days was taken";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("take the alarm out of service"), std::string::npos);
    }
}

TEST(AlarmMachine, OutOfServiceSuppressesUntilReturned) {
    auto step = on_remove_from_service(in(S::unack, L::alarm, L::alarm), kCli, 10);
    EXPECT_EQ(step.state.state, S::out_of_service);
    EXPECT_THROW(on_shelve(step.state, 100, kCli, 20), Error);
    step = on_process(step.state, L::none, false, 30);
    EXPECT_TRUE(step.events.empty());
    EXPECT_TRUE(on_acknowledge(step.state, kCli, 35).events.empty());
    step = on_return_to_service(step.state, kCli, 40);
    EXPECT_EQ(step.state.state, S::normal);
    EXPECT_EQ(step.events.at(0).kind, "in_service");
    step = on_remove_from_service(step.state, kCli, 50);
    step = on_process(step.state, L::alert, false, 60);
    step = on_return_to_service(step.state, kCli, 70);
    EXPECT_EQ(step.state.state, S::unack);
    EXPECT_EQ(step.state.level, L::alert);
}

TEST(AlarmMachine, NamesRoundTrip) {
    for (S s : {S::normal, S::unack, S::ack, S::rtn_unack, S::shelved, S::out_of_service}) {
        EXPECT_EQ(parse_isa_state(to_string(s)), s);
    }
    EXPECT_EQ(to_string(S::rtn_unack), "rtn_unack");
    EXPECT_EQ(to_string(L::none), "");
    EXPECT_EQ(parse_alarm_level("alert"), L::alert);
    EXPECT_EQ(to_string(AlarmActorKind::scada), "SCADA");
    EXPECT_THROW(parse_isa_state("HH"), Error);
}

}  // namespace
}  // namespace tlsmon
