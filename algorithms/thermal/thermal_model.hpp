#pragma once
// A zone quantity's thermal model (docs/thermal.md, "Model"): the value as a linear response
// to the lagged drivers (thermal_drivers.hpp),
//   y(t) = β₀ + β_T·T̃(t) + Σ_f β_f·S̃_f(t) [+ β_trend·(t − t₀)] + e(t),
// fitted on a training window by iteratively reweighted least squares with Huber's weights
// (Huber 1981; scale 1.4826·MAD), the two time constants chosen on a grid by the smallest
// robust residual scale. A prediction's σ: the error s of predicting a day the fit did not
// see (leave-one-day-out cross-validation over the training window: s = q95(|r|)/1.96; it
// holds the measurement noise of a typical epoch and what the model misses; never below the
// training's mean measurement σ), the coefficients' covariance projected on the epoch's
// drivers (inflated for the residuals' lag-1 autocorrelation ρ by (1 + ρ)/(1 − ρ), the AR(1)
// effective sample size, Zwiers & von Storch 1995), the extrapolation σ_x beyond the
// training's daily amplitudes, and the epoch's measurement variance in excess of the
// training's mean:
//   σ²(t) = max(s², mean σ_m²) + xᵀ C_β x + σ_x²(t) + max(0, σ_m²(t) − mean σ_m²).
// The solar terms scale with the day's amplitude a, a scaling tested only within the
// training's [a_min, a_max]; beyond, what the scaling adds is its own standard uncertainty,
// σ_x = |Σ β_f S̃_f|·|a − a_edge|/a (docs/thermal.md, "Extrapolation").
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/thermal/thermal_drivers.hpp"

namespace tlsmon::thermal {

// One measured value of the zone quantity.
struct Observation {
    double t = 0;      // UTC seconds
    double value = 0;  // e.g. m
    double sigma = 0;  // its measurement σ (e.g. the zone's LoD95 / 1.96), ≥ 0
};

struct ModelOptions {
    DriverOptions drivers;
    bool trend = false;  // a linear trend term (extrapolated beyond the training window)
    std::vector<double> surface_lags_h = {0.5, 1.0, 2.0};
    std::vector<double> section_lags_h = {1.0, 2.0, 3.0, 4.0, 6.0, 8.0};
    double huber_k = 1.345;  // 95 % efficiency at the normal distribution
    int max_iterations = 50;
    int min_observations = 48;  // with complete drivers
};

// The names of the model's terms, in coefficient order.
std::vector<std::string> model_terms(bool trend);

struct ThermalModel {
    Lags lags;
    bool trend = false;
    double trend_origin = 0;  // UTC seconds where the trend term is zero (training centre)
    Eigen::VectorXd coefficients;
    Eigen::MatrixXd covariance;       // of the coefficients (autocorrelation-inflated)
    double residual_sigma = 0;        // robust scale (1.4826·MAD) of the training residuals
    double prediction_sigma = 0;      // s: out of sample, leave-one-day-out (see the header)
    double day_mean_sigma = 0;        // RMS of the left-out days' mean residuals
    double day_spread_max = 0;        // the largest left-out day's spread / prediction_sigma
    int cv_days = 0;                  // days left out one by one (0: too few for it)
    double lag1_autocorrelation = 0;  // ρ of consecutive training residuals
    double measurement_variance = 0;  // mean σ_m² over the training observations
    double explained_share = 0;       // 1 − Σr²/Σ(y − ȳ)² (weighted)
    double training_from = 0, training_to = 0;        // UTC seconds of the first and last used
    double amplitude_min_c = 0, amplitude_max_c = 0;  // the daily amplitudes the training saw
    int observations = 0;                             // used (complete drivers)
    int downweighted = 0;                             // Huber weight < 1 at convergence
    int iterations = 0;
    bool converged = false;
};

// The fit, or nullopt with the reason in `why` (too few observations with complete drivers,
// a singular design: e.g. no sun in the window).
std::optional<ThermalModel> fit_thermal_model(const std::vector<AirReading>& air,
                                              const std::vector<Observation>& observations,
                                              const ModelOptions& options, std::string& why);

// The design row of one time's drivers.
Eigen::VectorXd design_row(const ThermalModel& model, const Drivers& drivers, double t);

// What a residual of an epoch the fit did not see is compared with: the left-out days' s,
// never below the training's mean measurement σ (the floor in σ(t) above; the model-health
// tests use it too).
double residual_reference_sigma(const ThermalModel& model);

// A day whose air amplitude lies beyond the training's by more than a quarter of their range:
// the compensation is flagged `extrapolated` (docs/thermal.md, "Extrapolation").
bool far_beyond_training_amplitudes(const ThermalModel& model, double daily_amplitude_c);

struct Prediction {
    double value = 0;
    double sigma = 0;                // of the residual y − value (see the header)
    double thermal_sigma = 0;        // of the value itself: without the measurement's noise
    double extrapolation_sigma = 0;  // the part of either from beyond the training's amplitudes
};
Prediction predict(const ThermalModel& model, const Drivers& drivers, double t,
                   double measurement_sigma);

}  // namespace tlsmon::thermal
