// The notifier's routing and delivery over a real epoch database, the clock given: each
// alarm event routed once, in order per channel; repeats suppressed; low levels held through
// quiet hours; failures retried with a doubling back-off that holds the channel's later
// rows; give-up after its time; one daily summary; every outcome an event. The channels
// here are functions that record what they are handed (the clients themselves are tested
// against real servers in test_process_notify.cpp).
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include "daemon/notify/notification_message.hpp"
#include "daemon/notify/notifier.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kNoon = 1'795'000'000 - 1'795'000'000 % 86400 + 12 * 3600;

struct Fixture {
    test::TempDir dir{"notifier"};
    EpochDatabase db = EpochDatabase::open(dir / "n.sqlite", EpochDatabase::Mode::read_write);
    std::vector<Notification> received;
    int failures_left = 0;  // the channel refuses this many sends first
    NotifyConfig config;

    Fixture() {
        db.site().upsert_zone("pier P3 top", "{}");
        db.alarms().upsert_rule({0, "P3 settlement", "pier P3 top", "m3c2_median_m", "{}", true});
        config.enabled = true;
        config.retry_initial = 10;
        config.retry_max = 40;
        config.give_up_after = 3600;
        config.routes = {NotifyRoute{{"office"}}};
    }
    Notifier notifier() {
        auto office = [this](const Notification& n) {
            if (failures_left > 0) {
                --failures_left;
                throw Error("connection refused");
            }
            received.push_back(n);
        };
        return Notifier(config, DashboardSite{"bridge-7", {"pier P3 top"}, kNoon - 86400, 0.5},
                        {{"office", office}});
    }
    void alarm(UtcSeconds t, const char* kind, const char* level, std::optional<double> value) {
        db.alarms().record_event(
            {t, "P3 settlement", kind, level, value, std::nullopt, "", "rule"});
    }
    std::vector<std::string> events(const std::string& kind) {
        SQLite::Database raw((dir / "n.sqlite").string(), SQLite::OPEN_READONLY);
        SQLite::Statement s(raw, "SELECT message FROM system_events WHERE kind = ? ORDER BY id");
        s.bind(1, kind);
        std::vector<std::string> out;
        while (s.executeStep()) out.push_back(s.getColumn(0).getString());
        return out;
    }
};

NotifyClock at(UtcSeconds utc, int local_second, const char* day = "2026-11-29") {
    return NotifyClock{utc, day, local_second};
}

TEST(Notifier, RoutesEachEventOnceAndDeliversInOrder) {
    Fixture f;
    f.alarm(kNoon - 60, "raise", "alert", 0.0251);
    f.alarm(kNoon - 30, "ack", "", std::nullopt);  // not a default kind: not routed
    f.alarm(kNoon - 20, "return", "alert", 0.001);
    f.alarm(kNoon - 10, "clear", "", 0.001);
    Notifier n = f.notifier();
    EXPECT_EQ(n.route(f.db, at(kNoon, 12 * 3600)), 3);
    EXPECT_EQ(n.route(f.db, at(kNoon + 1, 12 * 3600 + 1)), 0) << "routed once";
    EXPECT_EQ(n.deliver(f.db, kNoon), 3);
    ASSERT_EQ(f.received.size(), 3u);
    EXPECT_EQ(f.received[0].subject,
              "[tlsmon bridge-7] ALERT raise: P3 settlement m3c2_median_m = 25.10 mm");
    EXPECT_EQ(f.received[1].subject,
              "[tlsmon bridge-7] ALERT return: P3 settlement m3c2_median_m = 1.00 mm");
    // A clear carries no level itself: its alarm's (the raise's) stands in.
    EXPECT_EQ(f.received[2].subject,
              "[tlsmon bridge-7] ALERT clear: P3 settlement m3c2_median_m = 1.00 mm");
    const auto doc = Json::parse(f.received[0].body);
    EXPECT_EQ(doc.at("schema"), kNotificationSchema);
    EXPECT_EQ(doc.at("zone"), "pier P3 top");
    EXPECT_EQ(doc.at("value").get<double>(), 0.0251);
    EXPECT_EQ(doc.at("unit"), "m");
    EXPECT_EQ(doc.at("time"), format_utc(kNoon - 60));
    EXPECT_EQ(f.events("notify_sent").size(), 3u);
    EXPECT_EQ(n.deliver(f.db, kNoon + 100), 0) << "nothing is sent twice";
    for (const auto& row : f.db.notifications().all()) EXPECT_EQ(row.status, "sent");
}

TEST(Notifier, RepeatWithinTheWindowIsSuppressedAndSaidSo) {
    Fixture f;
    f.config.dedup_window = 1800;
    Notifier n = f.notifier();
    f.alarm(kNoon, "raise", "alert", 0.02);
    EXPECT_EQ(n.route(f.db, at(kNoon, 12 * 3600)), 1);
    f.alarm(kNoon + 600, "raise", "alert", 0.02);  // flapping: the same raise again
    f.alarm(kNoon + 600, "raise", "alarm", 0.03);  // a new level is news
    EXPECT_EQ(n.route(f.db, at(kNoon + 600, 12 * 3600 + 600)), 2);
    f.alarm(kNoon + 2000, "raise", "alert", 0.02);  // past the window
    EXPECT_EQ(n.route(f.db, at(kNoon + 2000, 12 * 3600 + 2000)), 1);
    EXPECT_EQ(n.deliver(f.db, kNoon + 2000), 3);
    const auto rows = f.db.notifications().all();
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[1].status, "suppressed");
    EXPECT_EQ(rows[2].status, "sent");
    EXPECT_EQ(rows[3].status, "sent");
    ASSERT_EQ(f.events("notify_suppressed").size(), 1u);
    EXPECT_NE(f.events("notify_suppressed")[0].find("within notify.dedup_window"),
              std::string::npos);
}

TEST(Notifier, QuietHoursHoldWarningsButNotAlarms) {
    Fixture f;
    f.config.quiet_hours = "22:00-06:00";
    Notifier n = f.notifier();
    const UtcSeconds night = kNoon + 11 * 3600;  // local 23:00 in this clock
    f.alarm(night, "raise", "warning", 0.004);
    EXPECT_EQ(n.route(f.db, at(night, 23 * 3600)), 1);
    f.db.alarms().upsert_rule({0, "system.stale", "pier P3 top", "", "{}", true});
    f.db.alarms().record_event(
        {night, "system.stale", "raise", "alarm", std::nullopt, std::nullopt, "", "rule"});
    EXPECT_EQ(n.route(f.db, at(night, 23 * 3600)), 1);
    EXPECT_EQ(n.deliver(f.db, night), 1);
    ASSERT_EQ(f.received.size(), 1u);
    EXPECT_EQ(f.received[0].subject, "[tlsmon bridge-7] ALARM raise: system.stale");
    EXPECT_EQ(n.deliver(f.db, night + 7 * 3600 - 1), 0) << "held until 06:00";
    EXPECT_EQ(n.deliver(f.db, night + 7 * 3600), 1);
    EXPECT_EQ(f.received[1].subject,
              "[tlsmon bridge-7] WARNING raise: P3 settlement m3c2_median_m = 4.00 mm");
    ASSERT_EQ(f.events("notify_held").size(), 1u);
    EXPECT_NE(f.events("notify_held")[0].find(format_utc(night + 7 * 3600)), std::string::npos);
}

TEST(Notifier, FailuresBackOffDoublingAndHoldTheChannelInOrder) {
    Fixture f;
    f.failures_left = 2;
    Notifier n = f.notifier();
    f.alarm(kNoon, "raise", "alert", 0.02);
    f.alarm(kNoon + 1, "return", "alert", 0.0);
    EXPECT_EQ(n.route(f.db, at(kNoon + 1, 12 * 3600)), 2);
    EXPECT_EQ(n.deliver(f.db, kNoon + 1), 0);  // attempt 1 fails: retry at +10 s
    EXPECT_EQ(n.deliver(f.db, kNoon + 5), 0) << "the return waits behind the raise";
    EXPECT_TRUE(f.received.empty());
    EXPECT_EQ(n.deliver(f.db, kNoon + 11), 0);  // attempt 2 fails: retry at +20 s
    EXPECT_EQ(n.deliver(f.db, kNoon + 30), 0);
    EXPECT_EQ(n.deliver(f.db, kNoon + 31), 2);
    ASSERT_EQ(f.received.size(), 2u);
    EXPECT_NE(f.received[0].subject.find("raise"), std::string::npos);
    EXPECT_NE(f.received[1].subject.find("return"), std::string::npos);
    const auto failed = f.events("notify_failed");
    ASSERT_EQ(failed.size(), 2u);
    EXPECT_NE(
        failed[0].find("attempt 1 failed (connection refused); next at " + format_utc(kNoon + 11)),
        std::string::npos)
        << failed[0];
    EXPECT_NE(
        failed[1].find("attempt 2 failed (connection refused); next at " + format_utc(kNoon + 31)),
        std::string::npos)
        << failed[1];
    EXPECT_EQ(f.db.notifications().all()[0].attempts, 3);
}

TEST(Notifier, GivesUpAfterItsTimeWithAnErrorEvent) {
    Fixture f;
    f.failures_left = 1000;
    Notifier n = f.notifier();
    f.alarm(kNoon, "raise", "alarm", 0.05);
    n.route(f.db, at(kNoon, 12 * 3600));
    for (UtcSeconds t = kNoon; t <= kNoon + 3600; t += 10) n.deliver(f.db, t);
    EXPECT_TRUE(f.events("notify_gave_up").empty());
    n.deliver(f.db, kNoon + 3601);
    const auto rows = f.db.notifications().all();
    EXPECT_EQ(rows[0].status, "failed");
    ASSERT_EQ(f.events("notify_gave_up").size(), 1u);
    EXPECT_NE(f.events("notify_gave_up")[0].find("connection refused"), std::string::npos);
    // 10, 20, 40, 40, ... s apart within the hour: the back-off stops doubling at retry_max.
    EXPECT_EQ(rows[0].attempts, 1 + 1 + 1 + (3600 - 70) / 40 + 1);
}

TEST(Notifier, OneDailySummaryAtItsLocalTime) {
    Fixture f;
    f.config.routes.clear();
    f.config.daily_summary = "07:00";
    f.config.summary_channels = {"office"};
    Notifier n = f.notifier();
    const UtcSeconds morning = kNoon - 5 * 3600;
    EXPECT_EQ(n.route(f.db, at(morning - 60, 7 * 3600 - 60)), 0);
    EXPECT_EQ(n.route(f.db, at(morning, 7 * 3600)), 1);
    EXPECT_EQ(n.deliver(f.db, morning), 1);
    EXPECT_EQ(n.route(f.db, at(morning + 3600, 8 * 3600)), 0) << "once a day";
    EXPECT_EQ(n.route(f.db, at(morning + 86400, 7 * 3600, "2026-11-30")), 1);
    EXPECT_EQ(n.deliver(f.db, morning + 86400), 1);
    const auto doc = Json::parse(f.received.at(0).body);
    EXPECT_EQ(doc.at("type"), "summary");
    EXPECT_EQ(doc.at("day"), "2026-11-29");
    EXPECT_EQ(doc.at("site").at("station"), "bridge-7");
    EXPECT_EQ(f.received.at(0).subject,
              "[tlsmon bridge-7] daily summary 2026-11-29: 0 epochs, 0 active alarms");
    EXPECT_NE(notification_text(doc).find("Active alarms:\n  none"), std::string::npos);
}

TEST(Notifier, OffItsCursorPassesOverTheHistory) {
    Fixture f;
    f.alarm(kNoon, "raise", "alert", 0.02);
    f.alarm(kNoon + 1, "clear", "", 0.0);
    EXPECT_EQ(pass_over_alarm_events(f.db), 2);
    EXPECT_EQ(pass_over_alarm_events(f.db), 0);
    Notifier n = f.notifier();
    EXPECT_EQ(n.route(f.db, at(kNoon + 2, 12 * 3600)), 0);
    f.alarm(kNoon + 3, "raise", "alert", 0.02);
    EXPECT_EQ(n.route(f.db, at(kNoon + 3, 12 * 3600)), 1);
}

}  // namespace
}  // namespace tlsmon
