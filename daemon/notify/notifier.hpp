#pragma once
// The notifier's two steps over the epoch database (docs/notifications.md), each one pass,
// given the clock:
//   route    the alarm events after the cursor -> one outbox row per channel their routes
//            name (suppressed when a repeat within dedup_window, held to the end of quiet
//            hours when below quiet_min_level), and the daily summary when its time came;
//            rows, cursor and events in one transaction: each event is routed once;
//   deliver  each pending row whose time came, oldest first, through its channel; a failure
//            waits retry_initial, doubling up to retry_max, and holds the channel's later rows
//            (a channel receives in order); a row due longer than give_up_after ago is given up.
// Every send, failure, suppression, hold and give-up is an event (system_events).
// A crash between a send and its record sends that notification again on restart: each
// carries its alarm event's id (`event_id`) for receivers that must not see it twice.
#include <map>
#include <optional>
#include <string>

#include "config/notify_config.hpp"
#include "daemon/http/dashboard_api.hpp"
#include "daemon/notify/notification_channel.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// The clock of one pass: UTC, and the local (the host's time zone) day and second of it.
struct NotifyClock {
    UtcSeconds utc = 0;
    std::string local_day;  // "2026-11-29"
    int local_second = 0;   // after local midnight
};
NotifyClock notify_clock(UtcSeconds utc);

class Notifier {
  public:
    // `channels`: one per configured channel name (make_channel). `site`: what the daily
    // summary says of the daemon (station, zones, start, disk).
    Notifier(NotifyConfig config, DashboardSite site, std::map<std::string, ChannelSend> channels);

    // Returns the rows made.
    int route(EpochDatabase& db, const NotifyClock& now);
    // Returns the notifications sent.
    int deliver(EpochDatabase& db, UtcSeconds now);

    // The daemon's knowledge of its disk, for the summary.
    void set_disk_free_share(std::optional<double> share) { site_.disk_free_share = share; }

  private:
    NotifyConfig config_;
    QuietHours quiet_;
    std::optional<int> summary_at_;
    DashboardSite site_;
    std::map<std::string, ChannelSend> channels_;
};

// With notifications off, the cursor follows the newest alarm event, so that turning them on
// later does not send the history. Returns the events passed over.
int pass_over_alarm_events(EpochDatabase& db);

}  // namespace tlsmon
