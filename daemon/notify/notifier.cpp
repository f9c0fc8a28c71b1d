#include "daemon/notify/notifier.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <set>

#include "daemon/notify/notification_message.hpp"

namespace tlsmon {

namespace {

constexpr int kBatch = 200;  // alarm events routed per transaction

SystemEvent event(UtcSeconds t, const char* level, const char* kind, std::string message) {
    return SystemEvent{t, level, kind, std::move(message), std::nullopt};
}

std::string row_name(const Notification& n) {
    return "notification " + std::to_string(n.id) + " (" + n.subject + ") to channel '" +
           n.channel + "'";
}

// Epochs acquired in the last 24 h, counted by status.
Json epochs_of_last_day(const EpochDatabase& db, UtcSeconds now) {
    Json counts = Json::object();
    for (const auto& e : epochs_json(db, TimeRange{now - 86400, now})) {
        const std::string status = e.at("status");
        counts[status] = counts.value(status, 0) + 1;
    }
    return counts;
}

}  // namespace

NotifyClock notify_clock(UtcSeconds utc) {
    const std::time_t t = static_cast<std::time_t>(utc);
    std::tm local{};
    localtime_r(&t, &local);
    char day[16];
    std::strftime(day, sizeof day, "%Y-%m-%d", &local);
    return NotifyClock{utc, day, local.tm_hour * 3600 + local.tm_min * 60 + local.tm_sec};
}

Notifier::Notifier(NotifyConfig config, DashboardSite site,
                   std::map<std::string, ChannelSend> channels)
    : config_(std::move(config)),
      quiet_(parse_quiet_hours(config_.quiet_hours).value_or(QuietHours{})),
      summary_at_(parse_time_of_day(config_.daily_summary)),
      site_(std::move(site)),
      channels_(std::move(channels)) {
    quiet_.min_level = config_.quiet_min_level;
}

int Notifier::route(EpochDatabase& db, const NotifyClock& now) {
    NotificationStore& store = db.notifications();
    const std::int64_t cursor = store.cursor();
    const auto events = store.alarm_events_after(cursor, kBatch);
    std::vector<Notification> rows;
    std::vector<SystemEvent> said;
    std::map<std::pair<std::string, std::string>, UtcSeconds> made;  // this batch's keys
    const auto add = [&](Notification n, AlarmLevel level) {
        const auto key = std::make_pair(n.channel, n.dedup_key);
        std::optional<UtcSeconds> last = store.last_created(n.channel, n.dedup_key);
        if (auto it = made.find(key); it != made.end()) last = it->second;
        if (config_.dedup_window > 0 && last && now.utc - *last < config_.dedup_window) {
            n.status = "suppressed";
            n.finished = now.utc;
            said.push_back(event(now.utc, "debug", "notify_suppressed",
                                 "'" + n.subject + "' to channel '" + n.channel +
                                     "' not sent: the same was notified at " + format_utc(*last) +
                                     ", within notify.dedup_window"));
        } else {
            made[key] = now.utc;
            if (const int wait = quiet_delay(quiet_, level, now.local_second); wait > 0) {
                n.due = now.utc + wait;
                said.push_back(event(now.utc, "info", "notify_held",
                                     "'" + n.subject + "' to channel '" + n.channel +
                                         "' held for the quiet hours until " + format_utc(n.due)));
            }
        }
        rows.push_back(std::move(n));
    };
    for (const RoutableAlarmEvent& e : events) {
        const AlarmLevel level =
            e.alarm_level.empty() ? AlarmLevel::none : parse_alarm_level(e.alarm_level);
        const auto channels = channels_for(config_.routes, e.event.rule, e.event.kind, level);
        if (channels.empty()) continue;
        const Json doc = alarm_notification(e, site_.station, config_.dashboard_url);
        for (const auto& channel : channels) {
            Notification n;
            n.channel = channel;
            n.created = n.due = now.utc;
            n.dedup_key = dedup_key(e.event.rule, e.event.kind, level);
            n.alarm_event_id = e.id;
            n.subject = notification_subject(doc);
            n.body = doc.dump();
            add(std::move(n), level);
        }
    }
    std::optional<std::string> summary_day;
    if (summary_at_ && !config_.summary_channels.empty() &&
        summary_due(*summary_at_, now.local_second, now.local_day, store.summary_day())) {
        summary_day = now.local_day;
        Json watched = Json::array();
        for (const AlarmRule& r : db.alarms().rules()) {
            if (r.enabled && !r.name.starts_with("system."))
                watched.push_back({{"rule", r.name}, {"zone", r.zone}, {"quantity", r.quantity}});
        }
        const Json doc = summary_notification(
            site_.station, now.local_day, now.utc, epochs_of_last_day(db, now.utc),
            std::move(watched),
            site_overview(db, site_, now.utc, now.utc, zone_overview(db, site_)),
            config_.dashboard_url);
        for (const auto& channel : config_.summary_channels) {
            Notification n;
            n.channel = channel;
            n.created = n.due = now.utc;
            n.dedup_key = "summary/" + now.local_day;
            n.subject = notification_subject(doc);
            n.body = doc.dump();
            rows.push_back(std::move(n));
        }
    }
    if (events.empty() && !summary_day) return 0;
    store.commit_routing(rows, events.empty() ? cursor : events.back().id, summary_day, said);
    return static_cast<int>(rows.size());
}

int Notifier::deliver(EpochDatabase& db, UtcSeconds now) {
    NotificationStore& store = db.notifications();
    std::set<std::string> held;  // channels whose oldest row waits for its retry
    int sent = 0;
    for (Notification n : store.pending(1000)) {
        if (held.count(n.channel)) continue;
        if (now - n.first_due > config_.give_up_after) {
            n.status = "failed";
            n.finished = now;
            store.record_attempt(
                n, event(now, "error", "notify_gave_up",
                         row_name(n) + " given up after " + std::to_string(n.attempts) +
                             " attempt(s) in " + duration_text(config_.give_up_after) +
                             (n.last_error.empty() ? "" : ": " + n.last_error)));
            continue;
        }
        if (n.due > now) {
            if (n.attempts > 0) held.insert(n.channel);
            continue;
        }
        const auto channel = channels_.find(n.channel);
        ++n.attempts;
        try {
            if (channel == channels_.end())
                throw Error("no channel of that name is configured any more");
            channel->second(n);
            n.status = "sent";
            n.finished = now;
            n.last_error.clear();
            store.record_attempt(
                n, event(now, "info", "notify_sent",
                         row_name(n) + " sent, attempt " + std::to_string(n.attempts)));
            ++sent;
        } catch (const std::exception& e) {
            const double wait =
                std::min(config_.retry_max, config_.retry_initial * std::pow(2.0, n.attempts - 1));
            n.due = now + static_cast<UtcSeconds>(std::ceil(wait));
            n.last_error = e.what();
            store.record_attempt(
                n, event(now, "warning", "notify_failed",
                         row_name(n) + ": attempt " + std::to_string(n.attempts) + " failed (" +
                             e.what() + "); next at " + format_utc(n.due)));
            held.insert(n.channel);
        }
    }
    return sent;
}

int pass_over_alarm_events(EpochDatabase& db) {
    NotificationStore& store = db.notifications();
    const std::int64_t cursor = store.cursor(), newest = store.newest_alarm_event();
    if (newest <= cursor) return 0;
    store.commit_routing({}, newest, std::nullopt, {});
    return static_cast<int>(newest - cursor);
}

}  // namespace tlsmon
