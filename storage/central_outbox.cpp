#include "storage/central_outbox.hpp"

#include <algorithm>

#include "storage/connection.hpp"

namespace tlsmon {

namespace {

// The site's history as outbox entries, per epoch in acquisition order and within it as the
// commit writes them (epoch, registration, zone results), events by their time. Each payload
// comes from the view the triggers use.
constexpr const char* kQueueHistory = R"sql(
INSERT INTO outbox (created, kind, payload)
SELECT unixepoch(), kind, payload FROM (
    SELECT acquired AS t, 0 AS rank, epoch_id AS k1, 0 AS k2, 'epoch' AS kind, payload
      FROM outbox_epochs
    UNION ALL
    SELECT acquired, 1, epoch_id, 0, 'registration', payload FROM outbox_registrations
    UNION ALL
    SELECT acquired, 2, epoch_id, zone_id * 1000000 + quantity_id, 'zone_result', payload
      FROM outbox_zone_results
    UNION ALL
    SELECT time, 3, id, 0, 'alarm_event', payload FROM outbox_alarm_events
    UNION ALL
    SELECT time, 3, id, 1, 'system_event', payload FROM outbox_system_events)
ORDER BY t, rank, k1, k2)sql";

}  // namespace

std::int64_t CentralOutbox::set_enabled(bool enabled) {
    return guarded(*c_, "switching the central outbox", [&]() -> std::int64_t {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        const bool was = c_->db.execAndGet("SELECT enabled FROM central_forward").getInt() != 0;
        if (was == enabled) return 0;
        const std::int64_t queued = enabled ? c_->db.exec(kQueueHistory) : 0;
        SQLite::Statement s(c_->db, "UPDATE central_forward SET enabled = ?");
        s.bind(1, enabled ? 1 : 0);
        s.exec();
        tx.commit();
        return queued;
    });
}

void CentralOutbox::set_forward_arrays(bool on) {
    guarded(*c_, "switching the central outbox's arrays", [&] {
        SQLite::Statement s(c_->db, "UPDATE central_forward SET forward_arrays = ?");
        s.bind(1, on ? 1 : 0);
        s.exec();
    });
}

CentralForwardState CentralOutbox::state() const {
    return guarded(*c_, "reading the central outbox", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::DEFERRED);
        SQLite::Statement s(c_->db,
                            "SELECT enabled, sent_upto, sent_at, last_error, last_error_at,"
                            " failing_since, (SELECT count(*) FROM outbox),"
                            " (SELECT min(created) FROM outbox), database_id, forward_arrays"
                            " FROM central_forward");
        s.executeStep();
        CentralForwardState st;
        st.enabled = s.getColumn(0).getInt() != 0;
        st.sent_upto = s.getColumn(1).getInt64();
        st.sent_at = optional_int64(s.getColumn(2));
        st.last_error = s.getColumn(3).getString();
        st.last_error_at = optional_int64(s.getColumn(4));
        st.failing_since = optional_int64(s.getColumn(5));
        st.pending = s.getColumn(6).getInt64();
        st.oldest_pending = optional_int64(s.getColumn(7));
        st.database_id = s.getColumn(8).getString();
        st.forward_arrays = s.getColumn(9).getInt() != 0;
        return st;
    });
}

std::vector<OutboxEntry> CentralOutbox::pending(int limit, int max_arrays) const {
    return guarded(*c_, "reading the central outbox", [&] {
        // The scan for kinds reads no payload (it follows kind in the row).
        SQLite::Statement s(c_->db,
                            "SELECT seq, created, kind, payload FROM outbox WHERE seq < coalesce(("
                            "SELECT seq FROM outbox WHERE kind = 'core_point_array' ORDER BY seq"
                            " LIMIT 1 OFFSET ?), 9223372036854775807) ORDER BY seq LIMIT ?");
        s.bind(1, std::max(1, max_arrays));
        s.bind(2, limit);
        std::vector<OutboxEntry> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getInt64(),
                           s.getColumn(2).getString(), s.getColumn(3).getString()});
        }
        return out;
    });
}

void CentralOutbox::mark_sent(std::int64_t seq, UtcSeconds at) {
    guarded(*c_, "marking central outbox entries sent", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement del(c_->db, "DELETE FROM outbox WHERE seq <= ?");
        del.bind(1, seq);
        del.exec();
        SQLite::Statement s(c_->db,
                            "UPDATE central_forward SET sent_upto = max(sent_upto, ?), sent_at = ?,"
                            " last_error = '', failing_since = NULL");
        s.bind(1, seq);
        s.bind(2, at);
        s.exec();
        tx.commit();
    });
}

void CentralOutbox::record_failure(const std::string& error, UtcSeconds at) {
    guarded(*c_, "recording a central forwarding failure", [&] {
        SQLite::Statement s(c_->db,
                            "UPDATE central_forward SET last_error = ?, last_error_at = ?,"
                            " failing_since = coalesce(failing_since, ?)");
        s.bind(1, error);
        s.bind(2, at);
        s.bind(3, at);
        s.exec();
    });
}

}  // namespace tlsmon
