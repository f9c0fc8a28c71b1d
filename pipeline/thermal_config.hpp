#pragma once
// What the thermal compensation needs of the site ([thermal], docs/thermal.md): where the site
// is (for the sun), which zone quantities to model, the training window and its refresh, the
// meteo it tolerates missing, and the model-health window.
#include <optional>
#include <string>
#include <vector>

#include "core/config_key.hpp"

namespace tlsmon {

struct ThermalConfig {
    bool enabled = false;
    std::optional<double> latitude_deg;   // required when enabled
    std::optional<double> longitude_deg;  // east positive
    std::vector<std::string> quantities = {"m3c2_median_m"};
    std::vector<std::string> zones;  // empty: every zone that stores a quantity named
    double training_days = 7.0;
    double refresh_days = 0.0;  // 0: the first model stays until refitted by hand
    bool trend = false;
    double max_meteo_gap_hours = 2.0;
    double health_window_hours = 24.0;
    double health_alpha = 0.001;
    bool located() const { return latitude_deg && longitude_deg; }
    bool operator==(const ThermalConfig&) const = default;
};

std::vector<SectionKey<ThermalConfig>> thermal_keys();

// The zone quantities the compensation of `quantity` ("m3c2_median_m") stores: the thermal
// prediction, the compensated residual, and the model-health statistics of its window.
struct ThermalQuantities {
    std::string predicted;    // m3c2_median_thermal_m
    std::string compensated;  // m3c2_median_compensated_m
    std::string drift;        // m3c2_median_thermal_drift_z: the window mean / its σ
    std::string spread;       // m3c2_median_thermal_spread_ratio: window spread / model's
};
ThermalQuantities thermal_quantities(const std::string& quantity);

// The section as a whole: a location when enabled. Each mistake is a ConfigError naming the key.
void check_thermal(TomlFields& t, const ThermalConfig& c);

}  // namespace tlsmon
