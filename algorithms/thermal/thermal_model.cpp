#include "algorithms/thermal/thermal_model.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/solar.hpp"
#include "core/statistics.hpp"

namespace tlsmon::thermal {

namespace {

constexpr double kDay = 86400.0;
constexpr Eigen::Index kFirstSolarTerm = 2;  // after the constant and the air (model_terms)

Eigen::VectorXd row_of(bool trend, double trend_origin, const Drivers& d, double t) {
    Eigen::VectorXd x(trend ? 7 : 6);
    x << 1.0, d.air_c, d.solar[0], d.solar[1], d.solar[2], d.solar[3];
    if (trend) x(6) = (t - trend_origin) / kDay;
    return x;
}

// IRLS with Huber's weights on a fixed design; the result's fields but the lags.
struct Irls {
    Eigen::VectorXd beta;
    Eigen::VectorXd residuals;
    Eigen::VectorXd weights;
    Eigen::MatrixXd normal_inverse;  // (Xᵀ W X)⁻¹
    double scale = 0;
    int iterations = 0;
    bool converged = false;
    bool singular = false;
};

Irls irls(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, double k, int max_iterations) {
    Irls r;
    r.weights = Eigen::VectorXd::Ones(y.size());
    for (r.iterations = 1; r.iterations <= max_iterations; ++r.iterations) {
        const Eigen::MatrixXd N = X.transpose() * r.weights.asDiagonal() * X;
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(N);
        if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
            ldlt.vectorD().minCoeff() <= 1e-12 * ldlt.vectorD().maxCoeff()) {
            r.singular = true;
            return r;
        }
        const Eigen::VectorXd beta = ldlt.solve(X.transpose() * (r.weights.asDiagonal() * y));
        r.residuals = y - X * beta;
        const double scale =
            kMadToSigma *
            median_and_mad({r.residuals.data(), r.residuals.data() + r.residuals.size()}).mad;
        const bool settled =
            r.beta.size() == beta.size() &&
            (beta - r.beta).cwiseAbs().maxCoeff() <= 1e-9 * (1.0 + beta.cwiseAbs().maxCoeff());
        r.beta = beta;
        r.scale = scale;
        r.normal_inverse = ldlt.solve(Eigen::MatrixXd::Identity(X.cols(), X.cols()));
        if (settled) {
            r.converged = true;
            break;
        }
        const double c = k * std::max(scale, std::numeric_limits<double>::min());
        for (Eigen::Index i = 0; i < y.size(); ++i) {
            const double a = std::abs(r.residuals(i));
            r.weights(i) = a <= c ? 1.0 : c / a;
        }
    }
    r.iterations = std::min(r.iterations, max_iterations);
    return r;
}

// The prediction's σ out of sample: every training day predicted by the model fitted on the
// other days (the chosen lags), σ = q95(|r|)/1.96 of those residuals, so that ±1.96σ holds
// 95 % of the errors on a day the fit did not see (never below the in-sample scale); the RMS
// of the days' mean residuals, how far a whole day's mean strays; and the largest of the days'
// spreads (1.4826·MAD about their mean) against σ, how unlike the others a day can be.
void cross_validate(const std::vector<Drivers>& drivers, const std::vector<double>& times,
                    const std::vector<Observation>& observations, ThermalModel& m,
                    const ModelOptions& options) {
    m.prediction_sigma = m.residual_sigma;
    m.day_mean_sigma = m.residual_sigma;
    std::vector<std::size_t> used;
    for (std::size_t i = 0; i < drivers.size(); ++i)
        if (drivers[i].complete && times[i] >= m.training_from && times[i] <= m.training_to)
            used.push_back(i);
    const auto p = static_cast<Eigen::Index>(m.coefficients.size());
    const auto day_of = [&](std::size_t i) {
        return static_cast<int>((times[i] - m.training_from) / kDay);
    };
    const int days = day_of(used.back()) + 1;
    std::vector<double> errors, day_means, day_spreads;
    for (int day = 0; day < days && days >= 3; ++day) {
        std::vector<std::size_t> fit_rows, test_rows;
        for (const std::size_t i : used) (day_of(i) == day ? test_rows : fit_rows).push_back(i);
        if (test_rows.size() < 24 || static_cast<Eigen::Index>(fit_rows.size()) < 4 * p) continue;
        Eigen::MatrixXd X(static_cast<Eigen::Index>(fit_rows.size()), p);
        Eigen::VectorXd y(X.rows());
        for (Eigen::Index r = 0; r < X.rows(); ++r) {
            const std::size_t i = fit_rows[static_cast<std::size_t>(r)];
            X.row(r) = row_of(m.trend, m.trend_origin, drivers[i], times[i]).transpose();
            y(r) = observations[i].value;
        }
        const Eigen::VectorXd column_scale =
            (X.colwise().squaredNorm() / double(X.rows())).cwiseSqrt().cwiseMax(1e-12);
        const Irls fit = irls(X * column_scale.cwiseInverse().asDiagonal(), y, options.huber_k,
                              options.max_iterations);
        if (fit.singular) continue;
        const Eigen::VectorXd beta = fit.beta.cwiseQuotient(column_scale);
        std::vector<double> left_out;  // the day's residuals
        for (const std::size_t i : test_rows) {
            left_out.push_back(observations[i].value -
                               row_of(m.trend, m.trend_origin, drivers[i], times[i]).dot(beta));
            errors.push_back(std::abs(left_out.back()));
        }
        double sum = 0;
        for (const double e : left_out) sum += e;
        day_means.push_back(sum / double(left_out.size()));
        for (double& e : left_out) e -= day_means.back();
        day_spreads.push_back(kMadToSigma * median_and_mad(left_out).mad);
    }
    if (day_means.size() < 3) return;
    std::sort(errors.begin(), errors.end());
    m.prediction_sigma = std::max(m.residual_sigma, quantile_of_sorted(errors, 0.95) / 1.96);
    double sum2 = 0;
    for (const double d : day_means) sum2 += d * d;
    m.day_mean_sigma = std::sqrt(sum2 / double(day_means.size()));
    m.cv_days = static_cast<int>(day_means.size());
    m.day_spread_max =
        *std::max_element(day_spreads.begin(), day_spreads.end()) / m.prediction_sigma;
}

// The part of the prediction that rests on daily amplitudes the training never saw: the solar
// terms scale with the day's amplitude a, a scaling tested only within the training's
// [a_min, a_max]; beyond, what the scaling adds, |Σ β_f S̃_f|·|a − a_edge|/a, is its own
// standard uncertainty (docs/thermal.md, "Extrapolation"). 0 within the training's amplitudes.
double extrapolation_sigma(const ThermalModel& model, const Drivers& drivers,
                           const Eigen::VectorXd& x) {
    const double a = drivers.daily_amplitude_c;
    const double edge = std::clamp(a, model.amplitude_min_c, model.amplitude_max_c);
    if (a == edge || a <= 0.0) return 0.0;
    const auto solar = static_cast<Eigen::Index>(drivers.solar.size());
    const double sun = model.coefficients.segment(kFirstSolarTerm, solar)
                           .dot(x.segment(kFirstSolarTerm, solar));  // ∝ a
    return std::abs(sun) * std::abs(a - edge) / a;
}

}  // namespace

std::vector<std::string> model_terms(bool trend) {
    std::vector<std::string> names = {"constant", "air"};
    for (const char* face : kFaceNames) names.push_back(std::string("solar_") + face);
    if (trend) names.push_back("trend_per_day");
    return names;
}

std::optional<ThermalModel> fit_thermal_model(const std::vector<AirReading>& air,
                                              const std::vector<Observation>& observations,
                                              const ModelOptions& options, std::string& why) {
    std::vector<double> times;
    times.reserve(observations.size());
    for (const Observation& o : observations) times.push_back(o.t);
    // One spin-up for the whole grid, so every pair of lags is scored on the same epochs.
    DriverOptions driver_options = options.drivers;
    if (driver_options.spin_up_h <= 0.0) {
        for (const double surface : options.surface_lags_h)
            for (const double section : options.section_lags_h)
                driver_options.spin_up_h =
                    std::max(driver_options.spin_up_h,
                             spin_up_seconds({surface, section}, options.drivers) / 3600.0);
    }
    const DriveTrack track = drive_track(air, times, driver_options);
    std::optional<ThermalModel> best;
    Irls best_fit;
    why = "no observation with complete drivers";
    for (const double surface : options.surface_lags_h) {
        for (const double section : options.section_lags_h) {
            const Lags lags{surface, section};
            const std::vector<Drivers> drivers = lagged_drivers(track, lags);
            std::vector<std::size_t> used;
            for (std::size_t i = 0; i < drivers.size(); ++i)
                if (drivers[i].complete) used.push_back(i);
            if (static_cast<int>(used.size()) < options.min_observations) {
                why = std::to_string(used.size()) + " observations with complete drivers (air " +
                      "readings covering the lags' spin-up), fewer than " +
                      std::to_string(options.min_observations);
                continue;
            }
            ThermalModel m;
            m.lags = lags;
            m.trend = options.trend;
            m.training_from = times[used.front()];
            m.training_to = times[used.back()];
            const auto [lowest, highest] = std::minmax_element(
                used.begin(), used.end(), [&drivers](std::size_t a, std::size_t b) {
                    return drivers[a].daily_amplitude_c < drivers[b].daily_amplitude_c;
                });
            m.amplitude_min_c = drivers[*lowest].daily_amplitude_c;
            m.amplitude_max_c = drivers[*highest].daily_amplitude_c;
            m.trend_origin = 0.5 * (m.training_from + m.training_to);
            const auto p = static_cast<Eigen::Index>(model_terms(m.trend).size());
            Eigen::MatrixXd X(static_cast<Eigen::Index>(used.size()), p);
            Eigen::VectorXd y(X.rows());
            double measurement_variance = 0;
            for (Eigen::Index r = 0; r < X.rows(); ++r) {
                const std::size_t i = used[static_cast<std::size_t>(r)];
                X.row(r) = row_of(m.trend, m.trend_origin, drivers[i], times[i]).transpose();
                y(r) = observations[i].value;
                measurement_variance += observations[i].sigma * observations[i].sigma;
            }
            // Columns scaled to unit RMS for the solve's conditioning (W/m² against °C).
            const Eigen::VectorXd column_scale =
                (X.colwise().squaredNorm() / double(X.rows())).cwiseSqrt().cwiseMax(1e-12);
            const Eigen::MatrixXd Xs = X * column_scale.cwiseInverse().asDiagonal();
            Irls fit = irls(Xs, y, options.huber_k, options.max_iterations);
            if (fit.singular) {
                why = "the design is singular (no sun or no change of the air in the window)";
                continue;
            }
            if (best && fit.scale >= best_fit.scale) continue;
            const Eigen::VectorXd unscale = column_scale.cwiseInverse();
            m.coefficients = fit.beta.cwiseProduct(unscale);
            m.residual_sigma = fit.scale;
            m.measurement_variance = measurement_variance / double(X.rows());
            m.observations = static_cast<int>(X.rows());
            m.iterations = fit.iterations;
            m.converged = fit.converged;
            m.downweighted = static_cast<int>((fit.weights.array() < 1.0).count());
            // ρ of consecutive residuals; the coefficient covariance s²(XᵀWX)⁻¹ inflated by
            // the AR(1) variance factor (1 + ρ)/(1 − ρ).
            const Eigen::VectorXd& e = fit.residuals;
            const double ee = e.squaredNorm();
            const double rho = ee > 0 ? e.head(e.size() - 1).dot(e.tail(e.size() - 1)) / ee : 0.0;
            m.lag1_autocorrelation = rho;
            const double r = std::clamp(rho, 0.0, 0.95);
            m.covariance = unscale.asDiagonal() * fit.normal_inverse * unscale.asDiagonal() *
                           (fit.scale * fit.scale * (1.0 + r) / (1.0 - r));
            const double mean = (fit.weights.array() * y.array()).sum() / fit.weights.sum();
            const double total = (fit.weights.array() * (y.array() - mean).square()).sum();
            const double left = (fit.weights.array() * e.array().square()).sum();
            m.explained_share = total > 0 ? 1.0 - left / total : 0.0;
            best = m;
            best_fit = std::move(fit);
        }
    }
    if (!best) return best;
    why.clear();
    cross_validate(lagged_drivers(track, best->lags), times, observations, *best, options);
    return best;
}

Eigen::VectorXd design_row(const ThermalModel& model, const Drivers& drivers, double t) {
    return row_of(model.trend, model.trend_origin, drivers, t);
}

double residual_reference_sigma(const ThermalModel& model) {
    // An unseen epoch's residual holds its whole measurement error, which no thermal driver
    // predicts; left-out days show less only where that error followed the drivers within the
    // training week, which another week need not repeat.
    return std::max(model.prediction_sigma, std::sqrt(model.measurement_variance));
}

bool far_beyond_training_amplitudes(const ThermalModel& model, double daily_amplitude_c) {
    const double slack = 0.25 * (model.amplitude_max_c - model.amplitude_min_c);
    return daily_amplitude_c < model.amplitude_min_c - slack ||
           daily_amplitude_c > model.amplitude_max_c + slack;
}

Prediction predict(const ThermalModel& model, const Drivers& drivers, double t,
                   double measurement_sigma) {
    const Eigen::VectorXd x = design_row(model, drivers, t);
    Prediction p;
    p.value = x.dot(model.coefficients);
    p.extrapolation_sigma = extrapolation_sigma(model, drivers, x);
    const double model_variance =
        x.dot(model.covariance * x) + p.extrapolation_sigma * p.extrapolation_sigma;
    const double s = residual_reference_sigma(model);
    const double excess =
        std::max(0.0, measurement_sigma * measurement_sigma - model.measurement_variance);
    p.sigma = std::sqrt(s * s + model_variance + excess);
    p.thermal_sigma = std::sqrt(std::max(0.0, model.prediction_sigma * model.prediction_sigma -
                                                  model.measurement_variance) +
                                model_variance);
    return p;
}

}  // namespace tlsmon::thermal
