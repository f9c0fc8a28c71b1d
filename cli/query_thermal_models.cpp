// `tlsmon query thermal-models`: the thermal compensation's models, every version of each zone
// quantity with its lags, coefficients and σ (docs/thermal.md; docs/schema.md,
// "thermal_models"), read-only; with --compensations one row per epoch and zone quantity in
// the time range: how it was compensated, or why not, and its model health.
#include <fmt/format.h>

#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

std::string joined(const std::vector<std::string>& names, const std::vector<double>& values) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < values.size(); ++i)
        out += fmt::format("{}{}={}", out.empty() ? "" : " ", names[i], values[i]);
    return out;
}

Table models_table(const std::vector<ThermalModelRow>& models) {
    Table t{{"zone", "quantity", "version", "fitted_epoch", "training_from", "training_to",
             "observations", "excluded", "surface_lag_h", "section_lag_h", "sigma_m",
             "residual_scale_m", "lag1_autocorrelation", "explained_share", "amplitude_min_c",
             "amplitude_max_c", "converged", "coefficients"},
            {}};
    for (const auto& m : models) {
        t.rows.push_back({m.zone, m.quantity, m.version, m.epoch, format_utc(m.training_from),
                          format_utc(m.training_to), m.observations, m.excluded, m.surface_lag_h,
                          m.section_lag_h, m.prediction_sigma, m.residual_sigma,
                          m.lag1_autocorrelation, m.explained_share, m.amplitude_min_c,
                          m.amplitude_max_c, m.converged, joined(m.terms, m.coefficients)});
    }
    return t;
}

Table compensations_table(const std::vector<StoredThermalCompensation>& rows) {
    Table t{{"epoch", "acquired", "zone", "quantity", "quality", "model_version", "air_age_h",
             "daily_amplitude_c", "drift_z", "spread_ratio", "drifted", "spread_grew", "reason"},
            {}};
    for (const auto& s : rows) {
        const auto& r = s.row;
        t.rows.push_back({s.epoch, format_utc(s.acquired), r.zone, r.quantity,
                          std::string(to_string(r.quality)), optional_cell(r.model_version),
                          optional_cell(r.air_age_h), optional_cell(r.daily_amplitude_c),
                          optional_cell(r.drift_z), optional_cell(r.spread_ratio), r.drifted,
                          r.spread_grew, r.reason});
    }
    return t;
}

std::optional<std::string> given(const std::string& s) {
    return s.empty() ? std::nullopt : std::optional<std::string>(s);
}

}  // namespace

int run_query_thermal_models(const ThermalModelsOptions& options) {
    return run_reporting_errors("query thermal-models", [&] {
        const auto db = open_for_reading(options.read);
        if (options.compensations) {
            print(std::cout,
                  compensations_table(db.thermal().compensations(
                      time_range(options.read), given(options.zone), given(options.quantity))),
                  options.read.format);
        } else {
            print(std::cout,
                  models_table(db.thermal().models(given(options.zone), given(options.quantity))),
                  options.read.format);
        }
    });
}

}  // namespace tlsmon
