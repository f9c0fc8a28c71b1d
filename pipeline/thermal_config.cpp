#include "pipeline/thermal_config.hpp"

namespace tlsmon {

std::vector<SectionKey<ThermalConfig>> thermal_keys() {
    using K = Keys<ThermalConfig>;
    return {
        K::flag(&ThermalConfig::enabled, "enabled",
                "Model each zone quantity named in `quantities` as a response to the lagged air "
                "temperature and the sun (docs/thermal.md), and store for every epoch the "
                "thermal prediction `<base>_thermal_m` and the compensated residual "
                "`<base>_compensated_m` (`<base>`: the name without `_m`), which alarm rules "
                "can watch."),
        K::optional_number(
            &ThermalConfig::latitude_deg, "latitude_deg", -90, 90, "°",
            "The site's latitude (WGS 84), for the sun's position; required when enabled."),
        K::optional_number(&ThermalConfig::longitude_deg, "longitude_deg", -180, 180, "°",
                           "The site's longitude, east positive; required when enabled."),
        K::names(&ThermalConfig::quantities, "quantities", "zone quantities ending in `_m`",
                 "The zone quantities modelled, e.g. `m3c2_median_m`."),
        K::names(&ThermalConfig::zones, "zones", "zone names; empty: every zone",
                 "The zones modelled; empty: every zone that stores one of the quantities."),
        K::number(&ThermalConfig::training_days, "training_days", 2, 365, "days",
                  "The training window: the first model is fitted once a zone quantity's series "
                  "is this long, on that window; a refit on the trailing window of this length."),
        K::number(&ThermalConfig::refresh_days, "refresh_days", 0, 365, "days",
                  "Refit the model when it is this old, on the trailing training window without "
                  "the epochs an alarm on the zone's compensated quantity was raised in; 0: never "
                  "(a refit can learn a slow structural change as thermal)."),
        K::flag(&ThermalConfig::trend, "trend",
                "Add a linear trend to the model (it is extrapolated beyond the training "
                "window: a week's trend held for months misleads; off by default)."),
        K::number(&ThermalConfig::max_meteo_gap_hours, "max_meteo_gap_hours", 0.25, 48, "h",
                  "A gap longer than this in the air temperatures of the lags' memory leaves "
                  "the epochs until a whole memory has passed uncompensated, as is an epoch "
                  "without its own meteo (quality `no_meteo`): stale temperatures are never "
                  "used."),
        K::number(&ThermalConfig::health_window_hours, "health_window_hours", 3, 720, "h",
                  "The trailing window of compensated residuals the model-health tests judge."),
        K::number(&ThermalConfig::health_alpha, "health_alpha", 1e-9, 0.1, "",
                  "Significance level of each model-health test (drift of the mean, growth of "
                  "the spread)."),
    };
}

ThermalQuantities thermal_quantities(const std::string& quantity) {
    const std::string base =
        quantity.ends_with("_m") ? quantity.substr(0, quantity.size() - 2) : quantity;
    return {base + "_thermal_m", base + "_compensated_m", base + "_thermal_drift_z",
            base + "_thermal_spread_ratio"};
}

void check_thermal(TomlFields& t, const ThermalConfig& c) {
    if (!c.enabled) return;
    if (!c.located())
        t.fail("latitude_deg",
               "the site's latitude_deg and longitude_deg are required when "
               "thermal compensation is enabled");
    if (c.quantities.empty()) t.fail("quantities", "name at least one zone quantity");
    for (const std::string& q : c.quantities) {
        if (q.size() < 3 || !q.ends_with("_m"))
            t.fail("quantities", "'" + q + "' is not a length quantity (ending in _m)");
    }
}

}  // namespace tlsmon
