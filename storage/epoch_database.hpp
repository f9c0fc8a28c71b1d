#pragma once
// The epoch database: one SQLite file holding every scan seen (an epoch), its processing
// status, the results of its analyses per zone (the time series), the reference-epoch
// cache, alarm state and the system's event log. Only storage/ knows SQL; everything here is
// plain structs.
//
// One EpochDatabase owns ONE connection; the stores it hands out are views of one concern
// each over that connection (epochs(), site(), results(), series(), reference_cache(),
// alarms(), events(), meteo(), registrations(), keypoint_models(), thermal(),
// notifications(), campaigns(), retention(), archive()) and live as long as it does.
//
// Durability: WAL journal, synchronous=FULL, foreign keys on, a busy timeout. All results of
// an epoch are written in ONE transaction together with its status (ResultsWriter::commit),
// so a crash leaves an epoch either complete or pending.
//
// Threads: one connection; use it from one thread at a time. Readers (tlsmon
// query/status/events, HTTP) open their own read_only connection; WAL lets them read while
// the daemon writes.
#include <chrono>
#include <filesystem>
#include <memory>

#include "storage/alarm_store.hpp"
#include "storage/archive_store.hpp"
#include "storage/campaign_store.hpp"
#include "storage/central_outbox.hpp"
#include "storage/epoch_results.hpp"
#include "storage/epochs.hpp"
#include "storage/event_log.hpp"
#include "storage/ids.hpp"
#include "storage/keypoint_models.hpp"
#include "storage/meteo_store.hpp"
#include "storage/notification_store.hpp"
#include "storage/reference_cache_store.hpp"
#include "storage/registration_store.hpp"
#include "storage/results_writer.hpp"
#include "storage/retention_store.hpp"
#include "storage/series_reader.hpp"
#include "storage/site.hpp"
#include "storage/storage_error.hpp"
#include "storage/thermal_store.hpp"

namespace tlsmon {

class EpochDatabase {
  public:
    enum class Mode { read_write, read_only };

    // read_write: creates the file if needed and applies the numbered migrations of schema/
    // not yet recorded in schema_migrations, each in its own transaction. A folder or file
    // the user cannot write is named in the StorageError with the missing permission.
    // read_only: writes nothing (no pragma that writes, no migration) and works for any user
    // who can read the file, also in a folder they cannot write.
    // A database newer than this binary knows is a StorageError in both modes; a read_only
    // open of an older database is one as well.
    static EpochDatabase open(const std::filesystem::path& path, Mode mode,
                              std::chrono::milliseconds busy_timeout = std::chrono::seconds(5));

    EpochDatabase(EpochDatabase&&) noexcept;
    EpochDatabase& operator=(EpochDatabase&&) noexcept;
    ~EpochDatabase();

    const std::filesystem::path& path() const;
    int schema_version() const;          // highest migration applied to this file
    static int latest_schema_version();  // highest migration this binary knows

    Epochs& epochs() { return epochs_; }
    const Epochs& epochs() const { return epochs_; }
    Site& site() { return site_; }
    const Site& site() const { return site_; }
    ResultsWriter& results() { return results_; }
    const SeriesReader& series() const { return series_; }
    ReferenceCacheStore& reference_cache() { return reference_cache_; }
    const ReferenceCacheStore& reference_cache() const { return reference_cache_; }
    AlarmStore& alarms() { return alarms_; }
    const AlarmStore& alarms() const { return alarms_; }
    EventLog& events() { return events_; }
    MeteoStore& meteo() { return meteo_; }
    const MeteoStore& meteo() const { return meteo_; }
    RegistrationStore& registrations() { return registrations_; }
    const RegistrationStore& registrations() const { return registrations_; }
    const KeypointModelStore& keypoint_models() const { return keypoint_models_; }
    const ThermalStore& thermal() const { return thermal_; }
    NotificationStore& notifications() { return notifications_; }
    const NotificationStore& notifications() const { return notifications_; }
    CampaignStore& campaigns() { return campaigns_; }
    const CampaignStore& campaigns() const { return campaigns_; }
    RetentionStore& retention() { return retention_; }
    const RetentionStore& retention() const { return retention_; }
    ArchiveStore& archive() { return archive_; }
    const ArchiveStore& archive() const { return archive_; }
    CentralOutbox& central_outbox() { return central_outbox_; }
    const CentralOutbox& central_outbox() const { return central_outbox_; }

  private:
    explicit EpochDatabase(std::unique_ptr<Connection> connection);

    // On the heap, so the stores' pointers to it survive a move of the EpochDatabase.
    std::unique_ptr<Connection> connection_;
    Epochs epochs_;
    Site site_;
    ResultsWriter results_;
    SeriesReader series_;
    ReferenceCacheStore reference_cache_;
    AlarmStore alarms_;
    EventLog events_;
    MeteoStore meteo_;
    RegistrationStore registrations_;
    KeypointModelStore keypoint_models_;
    ThermalStore thermal_;
    NotificationStore notifications_;
    CampaignStore campaigns_;
    RetentionStore retention_;
    ArchiveStore archive_;
    CentralOutbox central_outbox_;
};

}  // namespace tlsmon
