#include "alarms/notification_routing.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <charconv>

namespace tlsmon {

namespace {

bool matches_any(const std::vector<std::string>& patterns, std::string_view name) {
    const std::string n(name);
    return std::any_of(patterns.begin(), patterns.end(), [&](const std::string& p) {
        return ::fnmatch(p.c_str(), n.c_str(), 0) == 0;
    });
}

}  // namespace

std::vector<std::string> channels_for(const std::vector<NotifyRoute>& routes, std::string_view rule,
                                      std::string_view kind, AlarmLevel level) {
    std::vector<std::string> out;
    for (const NotifyRoute& r : routes) {
        if (level < r.min_level || !matches_any(r.rules, rule)) continue;
        if (std::find(r.events.begin(), r.events.end(), kind) == r.events.end()) continue;
        for (const auto& c : r.channels) {
            if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
        }
    }
    return out;
}

std::optional<int> parse_time_of_day(std::string_view text) {
    if (text.size() != 5 || text[2] != ':') return std::nullopt;
    int h = -1, m = -1;
    const auto a = std::from_chars(text.data(), text.data() + 2, h);
    const auto b = std::from_chars(text.data() + 3, text.data() + 5, m);
    if (a.ptr != text.data() + 2 || b.ptr != text.data() + 5) return std::nullopt;
    if (h < 0 || h > 23 || m < 0 || m > 59) return std::nullopt;
    return h * 3600 + m * 60;
}

std::optional<QuietHours> parse_quiet_hours(std::string_view text) {
    if (text.empty()) return QuietHours{};
    if (text.size() != 11 || text[5] != '-') return std::nullopt;
    const auto start = parse_time_of_day(text.substr(0, 5));
    const auto end = parse_time_of_day(text.substr(6, 5));
    if (!start || !end) return std::nullopt;
    return QuietHours{*start, *end};
}

int quiet_delay(const QuietHours& quiet, AlarmLevel level, int local_second) {
    if (quiet.start == quiet.end || level >= quiet.min_level) return 0;
    constexpr int kDay = 86400;
    // Time since the span began and its length, both modulo a day (spans over midnight).
    const int into = ((local_second - quiet.start) % kDay + kDay) % kDay;
    const int length = ((quiet.end - quiet.start) % kDay + kDay) % kDay;
    return into < length ? length - into : 0;
}

std::string dedup_key(std::string_view rule, std::string_view kind, AlarmLevel level) {
    return std::string(rule) + "/" + std::string(kind) + "/" + std::string(to_string(level));
}

bool summary_due(int summary_at, int local_second, std::string_view today,
                 std::string_view last_day) {
    return today != last_day && local_second >= summary_at;
}

}  // namespace tlsmon
