// Which channels an alarm event goes to, quiet hours and the daily summary's time.
#include <gtest/gtest.h>

#include "alarms/notification_routing.hpp"

namespace tlsmon {
namespace {

constexpr int kHour = 3600;

TEST(NotificationRouting, RoutesMatchRulePatternLevelAndEventKind) {
    NotifyRoute piers{{"office", "sms"}, {"P*"}, AlarmLevel::alert, {"raise", "escalate"}};
    NotifyRoute system{{"office"}, {"system.*"}, AlarmLevel::warning};
    const std::vector<NotifyRoute> routes{piers, system};
    EXPECT_EQ(channels_for(routes, "P3 settlement", "raise", AlarmLevel::alarm),
              (std::vector<std::string>{"office", "sms"}));
    EXPECT_TRUE(channels_for(routes, "P3 settlement", "raise", AlarmLevel::warning).empty())
        << "below the route's least level";
    EXPECT_TRUE(channels_for(routes, "P3 settlement", "clear", AlarmLevel::alarm).empty())
        << "a kind the route does not list";
    EXPECT_TRUE(channels_for(routes, "deck sag", "raise", AlarmLevel::alarm).empty());
    // The default kinds hold the returns to normal; a channel named by two routes comes once.
    EXPECT_EQ(channels_for(routes, "system.stale", "clear", AlarmLevel::alarm),
              (std::vector<std::string>{"office"}));
    const std::vector<NotifyRoute> twice{system, NotifyRoute{{"office"}, {"*"}}};
    EXPECT_EQ(channels_for(twice, "system.stale", "raise", AlarmLevel::alarm),
              (std::vector<std::string>{"office"}));
    EXPECT_TRUE(channels_for(routes, "system.stale", "ack", AlarmLevel::none).empty());
}

TEST(NotificationRouting, QuietHoursOverMidnightHoldLowLevelsUntilTheirEnd) {
    const auto quiet = parse_quiet_hours("22:00-06:30");
    ASSERT_TRUE(quiet);
    EXPECT_EQ(quiet->start, 22 * kHour);
    EXPECT_EQ(quiet->end, 6 * kHour + 1800);
    EXPECT_EQ(quiet->min_level, AlarmLevel::alarm);
    EXPECT_EQ(quiet_delay(*quiet, AlarmLevel::warning, 23 * kHour), 7 * kHour + 1800);
    EXPECT_EQ(quiet_delay(*quiet, AlarmLevel::alert, 2 * kHour), 4 * kHour + 1800);
    EXPECT_EQ(quiet_delay(*quiet, AlarmLevel::alert, 22 * kHour), 8 * kHour + 1800);
    EXPECT_EQ(quiet_delay(*quiet, AlarmLevel::alert, 6 * kHour + 1800), 0) << "the end is out";
    EXPECT_EQ(quiet_delay(*quiet, AlarmLevel::alert, 12 * kHour), 0);
    EXPECT_EQ(quiet_delay(*quiet, AlarmLevel::alarm, 23 * kHour), 0) << "critical goes at once";
    // A span within one day.
    const auto lunch = parse_quiet_hours("12:00-13:00");
    ASSERT_TRUE(lunch);
    EXPECT_EQ(quiet_delay(*lunch, AlarmLevel::warning, 12 * kHour + 600), 3000);
    EXPECT_EQ(quiet_delay(*lunch, AlarmLevel::warning, 11 * kHour), 0);
    // None.
    const auto none = parse_quiet_hours("");
    ASSERT_TRUE(none);
    EXPECT_EQ(quiet_delay(*none, AlarmLevel::warning, 23 * kHour), 0);
}

TEST(NotificationRouting, MalformedTimesAreRefused) {
    for (const char* bad : {"22-06", "24:00-06:00", "22:00-6:00", "22:60-06:00", "22:00 06:00"})
        EXPECT_FALSE(parse_quiet_hours(bad)) << bad;
    for (const char* bad : {"7:00", "07:0", "ab:cd", "07:00:00", ""})
        EXPECT_FALSE(parse_time_of_day(bad)) << bad;
    EXPECT_EQ(parse_time_of_day("07:05"), 7 * kHour + 300);
}

TEST(NotificationRouting, SummaryOncePerLocalDayFromItsTime) {
    EXPECT_FALSE(summary_due(7 * kHour, 6 * kHour, "2026-11-29", "2026-11-28"));
    EXPECT_TRUE(summary_due(7 * kHour, 7 * kHour, "2026-11-29", "2026-11-28"));
    EXPECT_TRUE(summary_due(7 * kHour, 20 * kHour, "2026-11-29", "")) << "late is still today's";
    EXPECT_FALSE(summary_due(7 * kHour, 20 * kHour, "2026-11-29", "2026-11-29"));
}

TEST(NotificationRouting, DedupKeyNamesRuleKindAndLevel) {
    EXPECT_EQ(dedup_key("P3", "raise", AlarmLevel::alert), "P3/raise/alert");
    EXPECT_NE(dedup_key("P3", "raise", AlarmLevel::alert),
              dedup_key("P3", "raise", AlarmLevel::alarm));
}

}  // namespace
}  // namespace tlsmon
