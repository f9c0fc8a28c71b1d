#pragma once
// The thermal compensation's rows (docs/thermal.md; schema 0021_thermal.sql): the versioned
// models of each zone quantity and how each epoch was compensated. Written by the epoch's
// commit (ResultsWriter); read by the thermal stage (the model in use, the air of the lags'
// memory, the epochs to leave out of a refit) and by `tlsmon query thermal-models`.
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct TimeRange;

// One fit, as stored: the kernel's ThermalModel (algorithms/thermal/thermal_model.hpp) in
// plain numbers.
struct ThermalModelRow {
    std::string zone, quantity;
    std::int64_t version = 0;  // from 1 per zone quantity; 0 in a commit: the next one
    EpochId epoch = 0;         // whose commit fitted it (filled when read)
    UtcSeconds training_from = 0, training_to = 0;
    std::int64_t observations = 0, excluded = 0;
    double surface_lag_h = 0, section_lag_h = 0;
    std::vector<std::string> terms;
    std::vector<double> coefficients;  // one per term
    std::vector<double> covariance;    // terms × terms, row-major
    double trend_origin = 0;
    double residual_sigma = 0, prediction_sigma = 0, day_mean_sigma = 0, day_spread_max = 0;
    std::int64_t cv_days = 0;
    double lag1_autocorrelation = 0;
    double measurement_variance = 0, explained_share = 0;
    double amplitude_min_c = 0, amplitude_max_c = 0;
    std::int64_t iterations = 0;
    bool converged = false;
};

enum class ThermalQuality { compensated, extrapolated, no_meteo, no_model };
const char* to_string(ThermalQuality q);

// How one epoch's zone quantity was compensated.
struct ThermalCompensationRow {
    std::string zone, quantity;
    ThermalQuality quality = ThermalQuality::no_model;
    std::optional<std::int64_t> model_version;  // set exactly when compensated (or extrapolated)
    std::string reason;                         // why not, or what is doubtful
    std::optional<double> air_age_h, daily_amplitude_c, drift_z, spread_ratio;
    bool drifted = false, spread_grew = false;
};

struct StoredThermalCompensation {
    EpochId epoch = 0;
    UtcSeconds acquired = 0;
    ThermalCompensationRow row;
};

// An air temperature of an epoch's meteo (its acquisition time).
struct AirTemperature {
    UtcSeconds acquired = 0;
    double temperature_c = 0;
};

class ThermalStore {
  public:
    explicit ThermalStore(Connection& connection) : c_(&connection) {}

    // The newest version of the zone quantity's model; none before the first fit.
    std::optional<ThermalModelRow> latest(const std::string& zone,
                                          const std::string& quantity) const;
    // Every version, by zone, quantity and version; only those of `zone` / `quantity` when
    // given.
    std::vector<ThermalModelRow> models(
        const std::optional<std::string>& zone = std::nullopt,
        const std::optional<std::string>& quantity = std::nullopt) const;
    // The compensations of the epochs acquired in the range, by acquisition time, zone and
    // quantity; only those of `zone` / `quantity` when given.
    std::vector<StoredThermalCompensation> compensations(
        const TimeRange& range, const std::optional<std::string>& zone = std::nullopt,
        const std::optional<std::string>& quantity = std::nullopt) const;
    // The compensation of the newest epoch acquired before `before`, if any.
    std::optional<StoredThermalCompensation> last_compensation(const std::string& zone,
                                                               const std::string& quantity,
                                                               UtcSeconds before) const;
    // The air temperatures of the epochs acquired in the range whose meteo was used, by time.
    std::vector<AirTemperature> air(const TimeRange& range) const;
    // The epochs acquired in the range while an alarm rule on the zone's `quantity` was raised
    // (from its raise or escalation to its return or clear).
    std::set<EpochId> alarmed_epochs(const std::string& zone, const std::string& quantity,
                                     const TimeRange& range) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
