#pragma once
// The epoch database: one SQLite file holding every scan seen (an epoch), its processing
// status, the results of its analyses per zone (the time series), alarm state and the
// system's event log. Only storage/ knows SQL; everything here is plain structs.
//
// Durability: WAL journal, synchronous=FULL, foreign keys on, a busy timeout. All results of
// an epoch are written in ONE transaction together with its status (commit_epoch), so a
// crash leaves an epoch either complete or pending.
//
// Threads: an EpochDatabase is one SQLite connection; use it from one thread at a time.
// Readers (tlsmon query/status, HTTP) open their own read-only connection; WAL lets them
// read while the daemon writes.
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

// An SQLite failure, with the SQL context in the message and the SQLite result codes kept.
class StorageError : public Error {
  public:
    StorageError(const std::string& what, int sqlite_code = 0, int extended_code = 0);
    int sqlite_code() const noexcept { return sqlite_code_; }
    int extended_code() const noexcept { return extended_code_; }
    // SQLITE_FULL or a disk I/O error (SQLITE_IOERR*): the disk, not the epoch, is at fault.
    // The daemon keeps the epoch (release_epoch) and retries later instead of failing it.
    bool disk_full() const noexcept;
    // SQLITE_BUSY / SQLITE_LOCKED after the busy timeout: another connection held the lock.
    bool busy() const noexcept;

  private:
    int sqlite_code_;
    int extended_code_;
};

using EpochId = std::int64_t;
using StationId = std::int64_t;
using ZoneId = std::int64_t;
using AlarmRuleId = std::int64_t;
// Times are UtcSeconds (core/utc_time.hpp converts to ISO-8601).

enum class EpochStatus { pending, processing, done, failed, rejected };
std::string_view to_string(EpochStatus status);
// Throws StorageError for an unknown name.
EpochStatus epoch_status_from_string(std::string_view name);

// ---- rows --------------------------------------------------------------------------------

struct Station {
    StationId id = 0;
    std::string name;
    std::array<double, 3> position{};  // project frame, metres
};

// A newly complete file in the ingest folder.
struct NewEpoch {
    std::string sha256;  // 64 lowercase hex digits: the identity of the scan
    UtcSeconds acquired = 0;
    std::filesystem::path file_path;
    std::int64_t file_size = 0;
    std::optional<StationId> station;
};

struct EpochInsert {
    EpochId id = 0;
    bool inserted = false;  // false: this sha256 was already an epoch; `id` is that epoch
};

// Milliseconds spent per stage (absent when the stage did not run).
struct EpochTimings {
    std::optional<double> read_ms, register_ms, analyse_ms, total_ms;
};

struct Epoch {
    EpochId id = 0;
    std::string sha256;
    UtcSeconds acquired = 0;
    UtcSeconds discovered = 0;  // when the row was inserted
    UtcSeconds updated = 0;     // last status change
    std::string file_path;
    std::int64_t file_size = 0;
    std::optional<StationId> station;
    EpochStatus status = EpochStatus::pending;
    std::string reason;  // why failed / rejected ("" otherwise)
    std::optional<std::int64_t> point_count;
    EpochTimings timings;
    std::optional<std::string> archive_path;  // where the file was moved (archive/quarantine)
};

// Registration of one epoch onto the reference targets (filled by the registration stage).
struct RegistrationRow {
    std::string method;                  // e.g. "targets-helmert"
    std::array<double, 16> transform{};  // 4x4 row-major, scan frame -> project frame
    std::int64_t target_count = 0;       // targets used
    double rms_m = 0;                    // RMS of the target residuals
    double max_residual_m = 0;
    std::optional<double> sigma0;     // a-posteriori standard deviation of unit weight
    bool accepted = false;            // passed the quality gate
    std::string quality_json = "{}";  // further quality figures, free form
};

struct TargetObservation {
    std::string target;                // name of the reference target
    std::string kind;                  // "sphere", "plane", ...
    std::array<double, 3> measured{};  // centre in the scan frame, metres
    std::array<double, 3> residual{};  // project frame, metres
    bool stable = true;                // passed the stability test
    bool used = true;                  // used in the transformation estimate
};

// Aggregate of one quantity over one zone in one epoch: one point of a time series.
struct ZoneResult {
    std::string zone;      // zone name (the zone must exist: upsert_zone)
    std::string quantity;  // e.g. "m3c2_mean_m", "keypoint_dz_m"
    double value = 0;
    std::optional<double> uncertainty;  // e.g. LoD95 or standard error, same unit as value
    std::int64_t n = 0;                 // number of core points / keypoints aggregated
    bool significant = false;           // |value| > LoD
};

// One value per core point (in the reference's core point order), stored as float32.
struct CorePointArray {
    std::string quantity;  // e.g. "m3c2_distance_m", "lod95_m"
    std::vector<float> values;
};

struct AlarmRule {
    AlarmRuleId id = 0;
    std::string name;  // unique
    std::string zone;
    std::string quantity;
    std::string definition_json = "{}";  // levels, deadband, delays: owned by the alarm code
    bool enabled = true;
};

// Current state of one rule in the ISA-18.2 state machine (state names owned by the alarm
// code: "normal", "unack", "ack", "rtn_unack", "shelved", ...).
struct AlarmState {
    std::string rule;  // rule name
    std::string state;
    std::string level;  // "", "H", "HH", ...
    UtcSeconds since = 0;
    std::optional<double> value;
    std::optional<EpochId> epoch;
};

struct AlarmEvent {
    UtcSeconds time = 0;
    std::string rule;  // rule name
    std::string kind;  // "raise", "clear", "ack", "shelve", ...
    std::string level;
    std::optional<double> value;
    std::optional<EpochId> epoch;
    std::string message;
};

struct SystemEvent {
    UtcSeconds time = 0;
    std::string level;  // "debug", "info", "warning", "error"
    std::string kind;   // "start", "stop", "disk_full", "config_reload", "quarantine", ...
    std::string message;
    std::optional<EpochId> epoch;
};

// Everything one processed epoch produces, written by commit_epoch in one transaction.
struct EpochResults {
    // done (analysed) or rejected (quality gate; reason required, zone results not allowed).
    EpochStatus outcome = EpochStatus::done;
    std::string reason;
    std::optional<std::int64_t> point_count;
    EpochTimings timings;
    std::optional<std::string> archive_path;
    std::optional<RegistrationRow> registration;
    std::vector<TargetObservation> targets;
    std::vector<ZoneResult> zone_results;
    std::vector<CorePointArray> core_point_arrays;
    std::vector<AlarmState> alarm_states;  // new states of the rules this epoch changed
    std::vector<AlarmEvent> alarm_events;
    std::vector<SystemEvent> system_events;
};

// ---- reads -------------------------------------------------------------------------------

struct TimeRange {
    std::optional<UtcSeconds> from;  // inclusive
    std::optional<UtcSeconds> to;    // inclusive
};

struct SeriesPoint {
    EpochId epoch = 0;
    UtcSeconds acquired = 0;
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
    std::string rule;  // alarm events only
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

// ---- the database ------------------------------------------------------------------------

class EpochDatabase {
  public:
    enum class Mode { read_write, read_only };

    // Opens (read_write: creates) the database and, read_write only, applies the numbered
    // migrations of schema/ not yet recorded in schema_migrations, each in its own
    // transaction. A database whose version is newer than this binary knows is a
    // StorageError (in both modes); a read_only open of an older database is one as well.
    static EpochDatabase open(const std::filesystem::path& path, Mode mode,
                              std::chrono::milliseconds busy_timeout = std::chrono::seconds(5));

    EpochDatabase(EpochDatabase&&) noexcept;
    EpochDatabase& operator=(EpochDatabase&&) noexcept;
    ~EpochDatabase();

    const std::filesystem::path& path() const;
    int schema_version() const;          // highest migration applied to this file
    static int latest_schema_version();  // highest migration this binary knows

    // -- stations
    StationId upsert_station(const std::string& name, const std::array<double, 3>& position);
    std::vector<Station> stations() const;

    // -- epochs
    // Insert-or-get by sha256: a new file becomes a `pending` epoch.
    EpochInsert insert_epoch(const NewEpoch& epoch);
    std::optional<Epoch> epoch(EpochId id) const;
    std::optional<Epoch> epoch_by_sha256(const std::string& sha256) const;
    // Pending epochs, oldest acquisition first (ties by id): the processing order.
    std::vector<Epoch> pending_epochs() const;
    // pending -> processing. False if the epoch is not pending (someone else took it).
    bool claim_epoch(EpochId id);
    // processing -> pending (e.g. disk full: retry later).
    void release_epoch(EpochId id);
    // processing -> failed / rejected with a reason; the file may have moved (quarantine).
    void fail_epoch(EpochId id, const std::string& reason,
                    std::optional<std::string> moved_to = std::nullopt);
    void reject_epoch(EpochId id, const std::string& reason,
                      std::optional<std::string> moved_to = std::nullopt);
    // The content of an epoch that was never read (pending, or failed without a file to
    // move because its file had vanished) was found again at `file` (renamed, copied in
    // again): the epoch now points at `file` and is pending. False if the epoch is in
    // another state.
    bool relocate_epoch(EpochId id, const std::filesystem::path& file);
    // At start: every `processing` epoch left by a crash goes back to `pending`. Returns how
    // many.
    std::int64_t recover_interrupted();
    // Everything of one epoch plus its status processing -> results.outcome, in ONE
    // transaction. On any error nothing of it is stored and the epoch stays `processing`.
    void commit_epoch(EpochId id, const EpochResults& results);

    // -- reference epoch (epoch 0 of the analyses)
    // Sets it once; setting the same epoch again is a no-op, another one a StorageError.
    void set_reference_epoch(EpochId id);
    std::optional<EpochId> reference_epoch() const;

    // -- zones and alarm rules (from the configuration, upserted at start and on reload)
    ZoneId upsert_zone(const std::string& name, const std::string& definition_json);
    std::vector<std::pair<std::string, std::string>> zones() const;  // name, definition
    AlarmRuleId upsert_alarm_rule(const AlarmRule& rule);
    std::vector<AlarmRule> alarm_rules() const;

    // -- alarm state and events outside an epoch commit (acknowledge from SCADA, shelving)
    void set_alarm_state(const AlarmState& state);
    std::vector<AlarmState> alarm_states() const;
    void record_alarm_event(const AlarmEvent& event);
    void record_system_event(const SystemEvent& event);

    // -- reads for status / query / events
    StatusSummary status_summary() const;
    std::vector<Epoch> epochs_in_range(const TimeRange& range) const;  // by acquisition time
    std::vector<SeriesPoint> series(const std::string& zone, const std::string& quantity,
                                    const TimeRange& range) const;
    // Distinct quantities stored for a zone.
    std::vector<std::string> quantities(const std::string& zone) const;
    // System and alarm events by time; `kind` filters on the event kind when given.
    std::vector<EventRow> events(const TimeRange& range,
                                 const std::optional<std::string>& kind = std::nullopt) const;
    std::optional<CorePointArray> core_point_array(EpochId id, const std::string& quantity) const;
    std::optional<RegistrationRow> registration(EpochId id) const;
    std::vector<TargetObservation> target_observations(EpochId id) const;
    std::int64_t database_bytes() const;  // main file + WAL on disk

    struct Impl;

  private:
    explicit EpochDatabase(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tlsmon
