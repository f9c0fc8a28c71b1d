#pragma once
// The central outbox (schema 0020, docs/central.md): what the site forwards to a central
// PostgreSQL, written by triggers in the transaction of the rows it copies, and the
// forwarder's state. Read and advanced by the daemon's forwarder thread alone.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"

namespace tlsmon {

struct Connection;

struct OutboxEntry {
    std::int64_t seq = 0;
    UtcSeconds created = 0;
    std::string kind;     // epoch, registration, zone_result, alarm_event, system_event,
                          // core_point_array
    std::string payload;  // a JSON object (schema/0020_central_outbox.sql)
};

struct CentralForwardState {
    bool enabled = false;
    bool forward_arrays = false;               // the epochs' core point arrays are queued too
    std::string database_id;                   // this database centrally (the batches' source)
    std::int64_t sent_upto = 0;                // the highest seq the central database committed
    std::optional<UtcSeconds> sent_at;         // when
    std::int64_t pending = 0;                  // entries not yet sent
    std::optional<UtcSeconds> oldest_pending;  // created time of the oldest of them
    std::string last_error;  // of the last attempt that failed ("" after a success)
    std::optional<UtcSeconds> last_error_at;
    std::optional<UtcSeconds> failing_since;  // first failure since the last success
};

class CentralOutbox {
  public:
    explicit CentralOutbox(Connection& connection) : c_(&connection) {}

    // Switches the triggers on or off. Switched on (from off), the site's whole history
    // (finished epochs, registrations, zone results, alarm and system events) is queued in
    // acquisition order in the same transaction, so the central copy is complete, also of
    // what was committed while forwarding was off; the central database ignores the rows it
    // already holds. Returns the number of entries queued from history.
    std::int64_t set_enabled(bool enabled);

    // Queues the core point arrays of the epochs committed from now on, or stops (schema 0022);
    // arrays committed while it was off are not queued afterwards.
    void set_forward_arrays(bool on);

    CentralForwardState state() const;
    // The oldest unsent entries in seq order: at most `limit`, and at most `max_arrays` core
    // point arrays (each some hundred kB of hex), ending before the next one.
    std::vector<OutboxEntry> pending(int limit, int max_arrays = 8) const;
    // The central database committed every entry up to `seq`: in one transaction they are
    // deleted, sent_upto advanced and the failure cleared. A seq at or below sent_upto (a
    // batch re-sent after a crash) changes nothing.
    void mark_sent(std::int64_t seq, UtcSeconds at);
    // An attempt failed; failing_since keeps the first failure's time.
    void record_failure(const std::string& error, UtcSeconds at);

  private:
    Connection* c_;
};

}  // namespace tlsmon
