#include "storage/notification_store.hpp"

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

constexpr const char* kNotificationColumns =
    "id, channel, created, first_due, due, status, attempts, dedup_key, alarm_event_id, subject,"
    " body, last_error, finished";

Notification read_row(SQLite::Statement& s) {
    Notification n;
    n.id = s.getColumn(0).getInt64();
    n.channel = s.getColumn(1).getString();
    n.created = s.getColumn(2).getInt64();
    n.first_due = s.getColumn(3).getInt64();
    n.due = s.getColumn(4).getInt64();
    n.status = s.getColumn(5).getString();
    n.attempts = s.getColumn(6).getInt();
    n.dedup_key = s.getColumn(7).getString();
    n.alarm_event_id = optional_int64(s.getColumn(8));
    n.subject = s.getColumn(9).getString();
    n.body = s.getColumn(10).getString();
    n.last_error = s.getColumn(11).getString();
    n.finished = optional_int64(s.getColumn(12));
    return n;
}

std::vector<Notification> read_rows(Connection& c, const std::string& where, int limit) {
    SQLite::Statement s(c.db, std::string("SELECT ") + kNotificationColumns +
                                  " FROM notifications " + where + " ORDER BY id LIMIT ?");
    s.bind(1, limit);
    std::vector<Notification> out;
    while (s.executeStep()) out.push_back(read_row(s));
    return out;
}

}  // namespace

std::int64_t NotificationStore::cursor() const {
    return guarded(*c_, "reading the notifier's cursor", [&] {
        SQLite::Statement s(c_->db, "SELECT alarm_event_id FROM notify_cursor WHERE id = 1");
        return s.executeStep() ? s.getColumn(0).getInt64() : std::int64_t{0};
    });
}

std::string NotificationStore::summary_day() const {
    return guarded(*c_, "reading the day of the last summary", [&] {
        SQLite::Statement s(c_->db, "SELECT summary_day FROM notify_cursor WHERE id = 1");
        return s.executeStep() ? s.getColumn(0).getString() : std::string();
    });
}

std::int64_t NotificationStore::newest_alarm_event() const {
    return guarded(*c_, "reading the newest alarm event", [&] {
        SQLite::Statement s(c_->db, "SELECT COALESCE(max(id), 0) FROM alarm_events");
        s.executeStep();
        return s.getColumn(0).getInt64();
    });
}

std::vector<RoutableAlarmEvent> NotificationStore::alarm_events_after(std::int64_t id,
                                                                      int limit) const {
    return guarded(*c_, "reading alarm events to notify", [&] {
        SQLite::Statement s(
            c_->db,
            "SELECT a.id, a.time, r.name, a.kind, a.level, a.value, a.epoch_id, a.message,"
            " a.actor, z.name, r.quantity,"
            " CASE WHEN a.level != '' THEN a.level ELSE COALESCE((SELECT p.level FROM"
            " alarm_events p WHERE p.rule_id = a.rule_id AND p.id < a.id AND p.level != ''"
            " ORDER BY p.id DESC LIMIT 1), '') END"
            " FROM alarm_events a JOIN alarm_rules r ON r.id = a.rule_id"
            " JOIN zones z ON z.id = r.zone_id WHERE a.id > ? ORDER BY a.id LIMIT ?");
        s.bind(1, id);
        s.bind(2, limit);
        std::vector<RoutableAlarmEvent> out;
        while (s.executeStep()) {
            RoutableAlarmEvent e;
            e.id = s.getColumn(0).getInt64();
            e.event = {s.getColumn(1).getInt64(),       s.getColumn(2).getString(),
                       s.getColumn(3).getString(),      s.getColumn(4).getString(),
                       optional_double(s.getColumn(5)), optional_int64(s.getColumn(6)),
                       s.getColumn(7).getString(),      s.getColumn(8).getString()};
            e.zone = s.getColumn(9).getString();
            e.quantity = s.getColumn(10).getString();
            e.alarm_level = s.getColumn(11).getString();
            out.push_back(std::move(e));
        }
        return out;
    });
}

std::optional<UtcSeconds> NotificationStore::last_created(const std::string& channel,
                                                          const std::string& key) const {
    return guarded(*c_, "looking up a repeated notification", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT max(created) FROM notifications WHERE channel = ? AND"
                            " dedup_key = ? AND status != 'suppressed'");
        s.bind(1, channel);
        s.bind(2, key);
        s.executeStep();
        return optional_int64(s.getColumn(0));
    });
}

void NotificationStore::commit_routing(const std::vector<Notification>& rows, std::int64_t cursor,
                                       const std::optional<std::string>& summary_day,
                                       const std::vector<SystemEvent>& events) {
    guarded(*c_, "storing notifications", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement insert(
            c_->db,
            "INSERT INTO notifications (channel, created, first_due, due, status, attempts,"
            " dedup_key, alarm_event_id, subject, body, last_error, finished)"
            " VALUES (?, ?, ?, ?, ?, 0, ?, ?, ?, ?, ?, ?)");
        for (const Notification& n : rows) {
            insert.bind(1, n.channel);
            insert.bind(2, n.created);
            insert.bind(3, n.due);  // first_due
            insert.bind(4, n.due);
            insert.bind(5, n.status);
            insert.bind(6, n.dedup_key);
            bind_optional(insert, 7, n.alarm_event_id);
            insert.bind(8, n.subject);
            insert.bind(9, n.body);
            insert.bind(10, n.last_error);
            bind_optional(insert, 11, n.finished);
            insert.exec();
            insert.reset();
        }
        SQLite::Statement move(c_->db,
                               "UPDATE notify_cursor SET alarm_event_id = ?,"
                               " summary_day = COALESCE(?, summary_day) WHERE id = 1");
        move.bind(1, cursor);
        bind_optional(move, 2, summary_day);
        move.exec();
        for (const auto& e : events) write_system_event(*c_, e);
        tx.commit();
    });
}

std::vector<Notification> NotificationStore::pending(int limit) const {
    return guarded(*c_, "reading pending notifications",
                   [&] { return read_rows(*c_, "WHERE status = 'pending'", limit); });
}

std::vector<Notification> NotificationStore::all() const {
    return guarded(*c_, "listing notifications", [&] { return read_rows(*c_, "", 1 << 30); });
}

void NotificationStore::record_attempt(const Notification& row, const SystemEvent& event) {
    guarded(*c_, "recording a notification's outcome", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement s(c_->db,
                            "UPDATE notifications SET status = ?, attempts = ?, due = ?,"
                            " last_error = ?, finished = ? WHERE id = ?");
        s.bind(1, row.status);
        s.bind(2, row.attempts);
        s.bind(3, row.due);
        s.bind(4, row.last_error);
        bind_optional(s, 5, row.finished);
        s.bind(6, row.id);
        s.exec();
        write_system_event(*c_, event);
        tx.commit();
    });
}

}  // namespace tlsmon
