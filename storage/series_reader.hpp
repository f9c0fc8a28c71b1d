#pragma once
// Reads for `tlsmon status|query|events` and the HTTP API: the status summary, epochs and
// time series by acquisition time, events, and the per-epoch results.
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/alarm_store.hpp"
#include "storage/epoch_results.hpp"
#include "storage/epochs.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct TimeRange {
    std::optional<UtcSeconds> from;  // inclusive
    std::optional<UtcSeconds> to;    // inclusive

    // The bounds for `BETWEEN ? AND ?`: an open end is the earliest / latest time there is.
    UtcSeconds lower() const { return from.value_or(std::numeric_limits<UtcSeconds>::min()); }
    UtcSeconds upper() const { return to.value_or(std::numeric_limits<UtcSeconds>::max()); }
};

struct SeriesPoint {
    EpochId epoch = 0;
    UtcSeconds acquired = 0;
    double value = 0;
    std::optional<double> uncertainty;
    std::int64_t n = 0;
    bool significant = false;
    // How the epoch was registered: its method ("targets", "icp", "reference", ...) or
    // "unregistered" (also for an epoch with no registration row); and whether the quality
    // gate accepted it.
    std::string datum;
    bool registration_accepted = false;
    // A campaign quantity's point (docs/campaigns.md, "Zone series"): the campaign it came
    // from; `epoch` is 0 and `datum` "campaign" then.
    std::optional<std::int64_t> campaign;
};

// The newest point of one zone quantity.
struct LatestValue {
    std::string zone;
    std::string quantity;
    SeriesPoint point;
};

// One zone quantity of one epoch, with the zone's stored definition (zones.definition).
struct EpochZoneValue {
    std::string zone;
    std::string definition;  // JSON
    std::string quantity;
    double value = 0;
    std::optional<double> uncertainty;
    std::int64_t n = 0;
    bool significant = false;
};

// A system or alarm event in one list (tlsmon events).
struct EventRow {
    UtcSeconds time = 0;
    std::string source;  // "system" or "alarm"
    std::string level;
    std::string kind;
    std::string message;
    std::optional<EpochId> epoch;
    std::string rule;   // alarm events only
    std::string actor;  // alarm events only: "rule", "SCADA", "CLI ..."
};

struct StatusSummary {
    std::map<EpochStatus, std::int64_t> epochs_by_status;  // every status present, 0 if none
    std::optional<Epoch> last_done;                        // latest acquisition among done
    std::int64_t backlog = 0;                              // pending + processing
    std::optional<UtcSeconds> oldest_pending;              // acquisition time
    std::optional<Epoch> last_failure;                     // latest failed or rejected
    std::optional<EpochId> reference_epoch;
    std::int64_t alarms_active = 0;  // rules whose state is not "normal"
    std::int64_t alarms_unacknowledged = 0;
    std::vector<AlarmState> alarm_states;  // every rule with a state
    std::int64_t database_bytes = 0;       // main file + WAL
    int schema_version = 0;
};

class SeriesReader {
  public:
    explicit SeriesReader(Connection& connection) : c_(&connection) {}

    StatusSummary status_summary() const;
    // By acquisition time; only those of `status` when given.
    std::vector<Epoch> epochs_in_range(const TimeRange& range,
                                       std::optional<EpochStatus> status = std::nullopt) const;
    // The time series of one quantity in one zone, by acquisition time; a campaign
    // quantity's (campaign_*) from the campaigns' zone rows.
    std::vector<SeriesPoint> points(const std::string& zone, const std::string& quantity,
                                    const TimeRange& range) const;
    // The same, one point at a time, for a reader that does not keep them all.
    void for_each_point(const std::string& zone, const std::string& quantity,
                        const TimeRange& range,
                        const std::function<void(const SeriesPoint&)>& visit) const;
    // The newest point (by acquisition time) of every zone quantity stored, by zone and
    // quantity name.
    std::vector<LatestValue> latest_values() const;
    // Every zone quantity the epoch stored, by zone and quantity name.
    std::vector<EpochZoneValue> epoch_zone_values(EpochId id) const;
    // Distinct quantities stored for a zone.
    std::vector<std::string> quantities(const std::string& zone) const;
    // System and alarm events by time; `kind` filters on the event kind when given.
    std::vector<EventRow> events(const TimeRange& range,
                                 const std::optional<std::string>& kind = std::nullopt) const;
    std::optional<CorePointArray> core_point_array(EpochId id, const std::string& quantity) const;
    // The pipeline stages that ran for the epoch, in order.
    std::vector<StageRun> stages(EpochId id) const;
    std::int64_t database_bytes() const;  // main file + WAL on disk

  private:
    void for_each_campaign_point(const std::string& zone, const std::string& quantity,
                                 const TimeRange& range,
                                 const std::function<void(const SeriesPoint&)>& visit) const;

    Connection* c_;
};

}  // namespace tlsmon
