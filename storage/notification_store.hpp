#pragma once
// The notification outbox (schema 0014, docs/notifications.md): the notifier's cursor over
// alarm_events, one row per notification and channel, and each row's outcome. Written by
// the daemon's notifier thread alone, through its own connection.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/alarm_store.hpp"
#include "storage/event_log.hpp"

namespace tlsmon {

// An alarm event as the notifier routes it.
struct RoutableAlarmEvent {
    std::int64_t id = 0;
    AlarmEvent event;
    std::string zone;
    std::string quantity;
    // The level of the alarm the event belongs to: its own, or for an event without one
    // (a clear, an acknowledgement) the rule's last level before it.
    std::string alarm_level;
};

struct Notification {
    std::int64_t id = 0;
    std::string channel;
    UtcSeconds created = 0;
    UtcSeconds first_due = 0;  // when it was to go first (after quiet hours); give_up_after
                               // counts from here
    UtcSeconds due = 0;
    std::string status = "pending";  // pending, sent, failed (given up), suppressed
    int attempts = 0;
    std::string dedup_key;
    std::optional<std::int64_t> alarm_event_id;
    std::string subject;
    std::string body;  // JSON
    std::string last_error;
    std::optional<UtcSeconds> finished;
};

class NotificationStore {
  public:
    explicit NotificationStore(Connection& connection) : c_(&connection) {}

    // The last alarm event routed, and the local day of the last daily summary.
    std::int64_t cursor() const;
    std::string summary_day() const;
    // The id of the newest alarm event (0: none).
    std::int64_t newest_alarm_event() const;
    // Alarm events after `id`, oldest first, at most `limit`.
    std::vector<RoutableAlarmEvent> alarm_events_after(std::int64_t id, int limit) const;
    // When a notification of `channel` with `key` was last created (suppressed ones aside).
    std::optional<UtcSeconds> last_created(const std::string& channel,
                                           const std::string& key) const;
    // In ONE transaction: the rows, the cursor moved to `cursor`, the summary day (when
    // given) and the events saying what was done.
    void commit_routing(const std::vector<Notification>& rows, std::int64_t cursor,
                        const std::optional<std::string>& summary_day,
                        const std::vector<SystemEvent>& events);
    // Pending rows, oldest first, at most `limit`.
    std::vector<Notification> pending(int limit) const;
    // A row's new status, attempts, due time, error and finish, with the event saying so,
    // in one transaction.
    void record_attempt(const Notification& row, const SystemEvent& event);
    std::vector<Notification> all() const;  // by id (tests, `tlsmon notify list`)

  private:
    Connection* c_;
};

}  // namespace tlsmon
