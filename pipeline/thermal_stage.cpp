#include "pipeline/thermal_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "algorithms/thermal/model_health.hpp"
#include "algorithms/thermal/thermal_model.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

constexpr double kDay = 86400.0;
constexpr double kHour = 3600.0;
constexpr double kZ95 = 1.96;  // the zone series' uncertainties are 95 % bounds (LoD95)

// The measurement σ of a stored value: its 95 % bound / 1.96; 0 when it has none.
double measurement_sigma(const std::optional<double>& uncertainty) {
    return uncertainty && std::isfinite(*uncertainty) ? *uncertainty / kZ95 : 0.0;
}

ThermalModelRow to_row(const thermal::ThermalModel& m, const std::string& zone,
                       const std::string& quantity) {
    ThermalModelRow r;
    r.zone = zone;
    r.quantity = quantity;
    r.training_from = static_cast<UtcSeconds>(m.training_from);
    r.training_to = static_cast<UtcSeconds>(m.training_to);
    r.amplitude_min_c = m.amplitude_min_c;
    r.amplitude_max_c = m.amplitude_max_c;
    r.observations = m.observations;
    r.surface_lag_h = m.lags.surface_h;
    r.section_lag_h = m.lags.section_h;
    r.terms = thermal::model_terms(m.trend);
    r.coefficients.assign(m.coefficients.data(), m.coefficients.data() + m.coefficients.size());
    const Eigen::MatrixXd rows = m.covariance.transpose();  // column-major storage → row-major
    r.covariance.assign(rows.data(), rows.data() + rows.size());
    r.trend_origin = m.trend_origin;
    r.residual_sigma = m.residual_sigma;
    r.prediction_sigma = m.prediction_sigma;
    r.day_mean_sigma = m.day_mean_sigma;
    r.day_spread_max = m.day_spread_max;
    r.cv_days = m.cv_days;
    r.lag1_autocorrelation = m.lag1_autocorrelation;
    r.measurement_variance = m.measurement_variance;
    r.explained_share = m.explained_share;
    r.iterations = m.iterations;
    r.converged = m.converged;
    return r;
}

thermal::ThermalModel from_row(const ThermalModelRow& r) {
    thermal::ThermalModel m;
    m.lags = {r.surface_lag_h, r.section_lag_h};
    m.trend = std::find(r.terms.begin(), r.terms.end(), "trend_per_day") != r.terms.end();
    m.trend_origin = r.trend_origin;
    const auto p = static_cast<Eigen::Index>(r.coefficients.size());
    m.coefficients = Eigen::Map<const Eigen::VectorXd>(r.coefficients.data(), p);
    m.covariance = Eigen::Map<const Eigen::MatrixXd>(r.covariance.data(), p, p).transpose();
    m.residual_sigma = r.residual_sigma;
    m.prediction_sigma = r.prediction_sigma;
    m.day_mean_sigma = r.day_mean_sigma;
    m.day_spread_max = r.day_spread_max;
    m.cv_days = static_cast<int>(r.cv_days);
    m.lag1_autocorrelation = r.lag1_autocorrelation;
    m.measurement_variance = r.measurement_variance;
    m.explained_share = r.explained_share;
    m.training_from = static_cast<double>(r.training_from);
    m.training_to = static_cast<double>(r.training_to);
    m.amplitude_min_c = r.amplitude_min_c;
    m.amplitude_max_c = r.amplitude_max_c;
    m.observations = static_cast<int>(r.observations);
    return m;
}

// What one epoch does for one zone quantity; the stage's shared reads.
class Compensation {
  public:
    Compensation(const ThermalConfig& config, StageContext& ctx)
        : config_(config), ctx_(ctx), t_(ctx.input.epoch.acquired) {
        options_.drivers.location = {config.latitude_deg.value_or(0),
                                     config.longitude_deg.value_or(0)};
        options_.drivers.max_gap_h = config.max_meteo_gap_hours;
        options_.trend = config.trend;
        if (const auto& m = ctx.input.meteo; m && m->values)
            own_air_ = thermal::AirReading{static_cast<double>(t_), m->values->air_temperature_c};
    }

    // The note's words for this zone quantity.
    std::string run(const ZoneResult& measured) {
        const std::string& zone = measured.zone;
        const std::string& quantity = measured.quantity;
        ThermalCompensationRow row;
        row.zone = zone;
        row.quantity = quantity;
        std::optional<ThermalModelRow> stored = ctx_.history.thermal->latest(zone, quantity);
        std::string fitted;
        if (due(stored)) {
            std::string why;
            if (auto model = fit(zone, quantity, measured, why)) {
                fitted = fmt::format("model v{} fitted", stored ? stored->version + 1 : 1);
                stored = *model;
                stored->version = 0;  // the next version, written in this commit
                ctx_.results.thermal_models.push_back(*model);
                event("info", "thermal_model",
                      fmt::format("{} {}: thermal model fitted on {} epochs (lags {:g} h + {:g} h, "
                                  "σ {:.2f} mm, {:.1f} % of the variance explained)",
                                  zone, quantity, model->observations, model->surface_lag_h,
                                  model->section_lag_h, model->prediction_sigma * 1e3,
                                  100.0 * model->explained_share));
            } else if (!stored) {
                row.reason = "no thermal model: " + why;
            }
        } else if (!stored) {
            row.reason = fmt::format(
                "no thermal model yet: the series is shorter than the "
                "training window ({:g} days)",
                config_.training_days);
        }
        if (stored) compensate(*stored, measured, row);
        note_transitions(row);
        ctx_.results.thermal_compensations.push_back(row);
        std::string words = zone + " " + to_string(row.quality);
        if (!fitted.empty()) words += " (" + fitted + ")";
        return words;
    }

  private:
    // No model and the series a training window long, or the model older than refresh_days.
    bool due(const std::optional<ThermalModelRow>& stored) const {
        if (stored) {
            return config_.refresh_days > 0 &&
                   t_ - stored->training_to >= config_.refresh_days * kDay;
        }
        return true;
    }

    // The air from `from` on: the stored meteo (read once per epoch, for the earliest time asked)
    // and this epoch's own.
    std::vector<thermal::AirReading> air(UtcSeconds from) {
        if (!stored_air_from_ || from < *stored_air_from_) {
            stored_air_.clear();
            for (const AirTemperature& a : ctx_.history.thermal->air({from, t_ - 1}))
                stored_air_.push_back({static_cast<double>(a.acquired), a.temperature_c});
            stored_air_from_ = from;
        }
        const auto first =
            std::lower_bound(stored_air_.begin(), stored_air_.end(), static_cast<double>(from),
                             [](const thermal::AirReading& a, double t) { return a.t < t; });
        std::vector<thermal::AirReading> out(first, stored_air_.end());
        if (own_air_) out.push_back(*own_air_);
        return out;
    }

    double memory_seconds() const {
        double longest = 0;
        for (const double s : options_.surface_lags_h)
            for (const double l : options_.section_lags_h)
                longest = std::max(longest, thermal::spin_up_seconds({s, l}, options_.drivers));
        return longest + kHour;
    }

    // The model on the training window ending with this epoch; nullopt with `why`.
    std::optional<ThermalModelRow> fit(const std::string& zone, const std::string& quantity,
                                       const ZoneResult& measured, std::string& why) {
        const double window = config_.training_days * kDay;
        const auto from = static_cast<UtcSeconds>(t_ - window);
        // The series reaches back a whole window: a point at or up to an hour before its start.
        auto points = ctx_.history.series->points(zone, quantity,
                                                  {from - static_cast<UtcSeconds>(kHour), t_ - 1});
        if (points.empty() || points.front().acquired > from) {
            why = fmt::format("the series is shorter than the training window ({:g} days)",
                              config_.training_days);
            return std::nullopt;
        }
        // Structural alarms (on the compensated series) mark epochs the model must not learn;
        // those of the raw series fire with the very daily swing it is to learn.
        std::erase_if(points, [from](const SeriesPoint& p) { return p.acquired < from; });
        const std::set<EpochId> alarmed = ctx_.history.thermal->alarmed_epochs(
            zone, thermal_quantities(quantity).compensated, {from, t_});
        std::vector<thermal::Observation> observations;
        std::int64_t excluded = 0;
        for (const SeriesPoint& p : points) {
            if (p.datum == kUnregistered || !p.registration_accepted || alarmed.contains(p.epoch)) {
                ++excluded;
                continue;
            }
            observations.push_back(
                {static_cast<double>(p.acquired), p.value, measurement_sigma(p.uncertainty)});
        }
        observations.push_back(
            {static_cast<double>(t_), measured.value, measurement_sigma(measured.uncertainty)});
        // The air from the lags' memory before the window on (drivers need a spin-up).
        const auto air_readings = air(static_cast<UtcSeconds>(from - memory_seconds()));
        thermal::ModelOptions options = options_;
        options.drivers.spin_up_h = 0;
        const auto model = thermal::fit_thermal_model(air_readings, observations, options, why);
        if (!model) return std::nullopt;
        ThermalModelRow row = to_row(*model, zone, quantity);
        row.excluded = excluded;
        return row;
    }

    void compensate(const ThermalModelRow& stored, const ZoneResult& measured,
                    ThermalCompensationRow& row) {
        const thermal::ThermalModel model = from_row(stored);
        const auto memory = thermal::spin_up_seconds(model.lags, options_.drivers) +
                            config_.max_meteo_gap_hours * kHour + kHour;
        const auto drivers =
            thermal::thermal_drivers(air(static_cast<UtcSeconds>(t_ - memory)),
                                     {static_cast<double>(t_)}, model.lags, options_.drivers);
        const thermal::Drivers& d = drivers.front();
        row.daily_amplitude_c = d.daily_amplitude_c;
        if (std::isfinite(d.air_age_h)) row.air_age_h = d.air_age_h;
        // The epoch's own air or nothing: an older reading held is a stale temperature.
        if (!own_air_ || !d.complete) {
            row.quality = ThermalQuality::no_meteo;
            row.reason = !own_air_ ? "this epoch has no meteo: the thermal part is not known"
                                   : fmt::format(
                                         "the air temperatures of the last {:.0f} h hold a "
                                         "gap longer than {:g} h",
                                         memory / kHour, config_.max_meteo_gap_hours);
            return;
        }
        row.model_version = stored.version;
        row.quality = ThermalQuality::compensated;
        if (thermal::far_beyond_training_amplitudes(model, d.daily_amplitude_c)) {
            row.quality = ThermalQuality::extrapolated;
            row.reason = fmt::format(
                "daily amplitude {:.1f} °C outside the training's {:.1f} .. "
                "{:.1f} °C",
                d.daily_amplitude_c, stored.amplitude_min_c, stored.amplitude_max_c);
        }
        const double t = static_cast<double>(t_);
        const double sigma_m = measurement_sigma(measured.uncertainty);
        const thermal::Prediction p = thermal::predict(model, d, t, sigma_m);
        const double residual = measured.value - p.value;
        const ThermalQuantities names = thermal_quantities(measured.quantity);
        auto& out = ctx_.results.zone_results;
        out.push_back(
            {measured.zone, names.predicted, p.value, kZ95 * p.thermal_sigma, measured.n, false});
        const double bound = kZ95 * p.sigma;
        out.push_back({measured.zone, names.compensated, residual, bound, measured.n,
                       std::abs(residual) > bound});
        health(stored, model, residual, row);
    }

    // The compensated residuals of the trailing window (of this model version) and this one.
    void health(const ThermalModelRow& stored, const thermal::ThermalModel& model, double residual,
                ThermalCompensationRow& row) {
        const ThermalQuantities names = thermal_quantities(row.quantity);
        const auto from = static_cast<UtcSeconds>(
            std::max<double>(t_ - config_.health_window_hours * kHour, stored.training_to + 1));
        std::vector<double> residuals;
        if (stored.version > 0) {
            for (const SeriesPoint& p :
                 ctx_.history.series->points(row.zone, names.compensated, {from, t_ - 1}))
                residuals.push_back(p.value);
        }
        residuals.push_back(residual);
        const thermal::ModelHealth h =
            thermal::model_health(model, residuals,
                                  {.min_residuals = 24,
                                   .window_h = config_.health_window_hours,
                                   .alpha = config_.health_alpha});
        if (!h.judged) return;
        row.drift_z = h.drift_z;
        row.spread_ratio = h.spread_ratio;
        row.drifted = h.drifted;
        row.spread_grew = h.spread_grew;
        auto& out = ctx_.results.zone_results;
        const auto n = static_cast<std::int64_t>(residuals.size());
        out.push_back({row.zone, names.drift, h.drift_z, h.drift_critical, n, h.drifted});
        out.push_back(
            {row.zone, names.spread, h.spread_ratio, h.spread_critical, n, h.spread_grew});
    }

    // An event when the quality or the model's health changes from the previous epoch's.
    void note_transitions(const ThermalCompensationRow& row) {
        const auto previous = ctx_.history.thermal->last_compensation(row.zone, row.quantity, t_);
        const std::string what = row.zone + " " + row.quantity;
        const auto usable = [](ThermalQuality q) {
            return q == ThermalQuality::compensated || q == ThermalQuality::extrapolated;
        };
        const bool was_usable = previous && usable(previous->row.quality);
        if (previous && was_usable != usable(row.quality)) {
            const std::string level = usable(row.quality) ? "info" : "warning";
            event(level, "thermal_compensation",
                  fmt::format("{}: {} (was {}){}", what, to_string(row.quality),
                              to_string(previous->row.quality),
                              row.reason.empty() ? "" : ": " + row.reason));
        } else if (!previous && !usable(row.quality) && !row.reason.empty() &&
                   row.quality == ThermalQuality::no_meteo) {
            event("warning", "thermal_compensation", what + ": " + row.reason);
        }
        const bool was_drifted = previous && previous->row.drifted;
        const bool was_spread = previous && previous->row.spread_grew;
        if (row.drifted != was_drifted || row.spread_grew != was_spread) {
            const bool ill = row.drifted || row.spread_grew;
            std::string findings;
            if (row.drifted)
                findings += fmt::format("the residuals' mean drifted (z = {:.1f})", *row.drift_z);
            if (row.spread_grew)
                findings += fmt::format("{}the residuals' spread is {:.1f}× the model's",
                                        findings.empty() ? "" : "; ", *row.spread_ratio);
            event(ill ? "warning" : "info", "thermal_model_health",
                  ill ? what + ": the thermal model no longer describes the structure: " + findings
                      : what + ": the residuals are back within the thermal model's σ");
        }
    }

    void event(const std::string& level, const std::string& kind, const std::string& message) {
        ctx_.results.system_events.push_back(
            SystemEvent{now_utc(), level, kind, message, ctx_.input.epoch.id});
    }

    const ThermalConfig& config_;
    StageContext& ctx_;
    UtcSeconds t_;
    thermal::ModelOptions options_;
    std::optional<thermal::AirReading> own_air_;
    std::vector<thermal::AirReading> stored_air_;  // sorted by time
    std::optional<UtcSeconds> stored_air_from_;
};

}  // namespace

StageVerdict ThermalStage::run(StageContext& ctx) const {
    if (!ctx.history.thermal || !ctx.history.series)
        return {"", "not compensated: a single epoch has no thermal history"};
    // The zone quantities to compensate, as the earlier stages wrote them.
    std::vector<ZoneResult> measured;
    for (const ZoneResult& r : ctx.results.zone_results) {
        const bool named = std::find(config_.quantities.begin(), config_.quantities.end(),
                                     r.quantity) != config_.quantities.end();
        const bool zone =
            config_.zones.empty() ||
            std::find(config_.zones.begin(), config_.zones.end(), r.zone) != config_.zones.end();
        if (named && zone) measured.push_back(r);
    }
    if (measured.empty()) return {"", "nothing to compensate"};
    Compensation compensation(config_, ctx);
    std::string note;
    for (const ZoneResult& r : measured) note += (note.empty() ? "" : ", ") + compensation.run(r);
    return {"", note};
}

}  // namespace tlsmon
