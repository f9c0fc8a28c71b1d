// The epoch database: its connection (open_connection.cpp) and the stores over it.
#include "storage/epoch_database.hpp"

#include <algorithm>
#include <chrono>

#include "storage/connection.hpp"
#include "storage/open_connection.hpp"
#include "storage/schema_migrations.hpp"

namespace tlsmon {

void throw_storage(const Connection& c, const std::string& what) {
    throw StorageError(c.path.string() + ": " + what);
}

int EpochDatabase::latest_schema_version() {
    int latest = 0;
    for (const auto& m : schema_migrations()) latest = std::max(latest, m.version);
    return latest;
}

EpochDatabase EpochDatabase::open(const std::filesystem::path& path, Mode mode,
                                  std::chrono::milliseconds busy_timeout) {
    return EpochDatabase(mode == Mode::read_write ? open_read_write(path, busy_timeout)
                                                  : open_read_only(path, busy_timeout));
}

EpochDatabase::EpochDatabase(std::unique_ptr<Connection> connection)
    : connection_(std::move(connection)),
      epochs_(*connection_),
      site_(*connection_),
      results_(*connection_),
      series_(*connection_),
      reference_cache_(*connection_),
      alarms_(*connection_),
      events_(*connection_),
      meteo_(*connection_),
      registrations_(*connection_),
      keypoint_models_(*connection_),
      thermal_(*connection_),
      notifications_(*connection_),
      campaigns_(*connection_),
      retention_(*connection_),
      archive_(*connection_),
      central_outbox_(*connection_) {}
EpochDatabase::EpochDatabase(EpochDatabase&&) noexcept = default;
EpochDatabase& EpochDatabase::operator=(EpochDatabase&&) noexcept = default;
EpochDatabase::~EpochDatabase() = default;

const std::filesystem::path& EpochDatabase::path() const {
    return connection_->path;
}
int EpochDatabase::schema_version() const {
    return connection_->version;
}

}  // namespace tlsmon
