#pragma once
// Which alarm events go to which notification channel, and when (docs/notifications.md):
// routes match a rule name (shell patterns, fnmatch(3)), a least level and the kinds of
// event; a repeat of the same rule, kind and level inside the de-duplication window is
// suppressed; during quiet hours an event below the configured level waits until they end.
// Pure: the caller supplies the clock (UTC, and the local second of the day).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "alarms/alarm_machine.hpp"

namespace tlsmon {

struct NotifyRoute {
    std::vector<std::string> channels;       // [[notify.channel]] names
    std::vector<std::string> rules = {"*"};  // patterns on the rule name ("pier*", "system.*")
    AlarmLevel min_level = AlarmLevel::warning;
    // Alarm event kinds (alarms/alarm_machine.hpp): by default the annunciations and the
    // returns to normal.
    std::vector<std::string> events = {"raise", "escalate", "return", "clear"};
};

// The channels an event of `rule` of `kind` goes to, each once, in the order the routes
// name them. `level` is the level of the alarm the event belongs to (a clear carries none
// itself: its alarm's last level).
std::vector<std::string> channels_for(const std::vector<NotifyRoute>& routes, std::string_view rule,
                                      std::string_view kind, AlarmLevel level);

// A daily span of local time "HH:MM-HH:MM" (it may run over midnight); start == end: none.
struct QuietHours {
    int start = 0;  // seconds after local midnight
    int end = 0;
    AlarmLevel min_level = AlarmLevel::alarm;  // events at or above this are sent at once
};
// Parses "22:00-06:00" ("" = none); nullopt when malformed.
std::optional<QuietHours> parse_quiet_hours(std::string_view text);
// Parses "07:30" into seconds after midnight; nullopt when malformed.
std::optional<int> parse_time_of_day(std::string_view text);

// Seconds an event of `level` must wait at local second of the day `local_second`: until
// the quiet hours end when they hold and the level is below their min_level, else 0.
int quiet_delay(const QuietHours& quiet, AlarmLevel level, int local_second);

// "rule/kind/level": two events with the same key inside the de-duplication window are one
// notification.
std::string dedup_key(std::string_view rule, std::string_view kind, AlarmLevel level);

// Whether the daily summary at local second `summary_at` is due: the local day `today`
// ("2026-11-29") has none yet (`last_day`) and its time has come.
bool summary_due(int summary_at, int local_second, std::string_view today,
                 std::string_view last_day);

}  // namespace tlsmon
