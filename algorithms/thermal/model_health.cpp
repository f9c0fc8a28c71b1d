#include "algorithms/thermal/model_health.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "core/statistics.hpp"

namespace tlsmon::thermal {

ModelHealth model_health(const ThermalModel& model, const std::vector<double>& residuals,
                         const HealthOptions& options) {
    ModelHealth h;
    h.residuals = static_cast<int>(residuals.size());
    const double s = residual_reference_sigma(model);
    if (h.residuals < options.min_residuals || s <= 0.0) return h;
    h.judged = true;
    const double rho = std::clamp(model.lag1_autocorrelation, 0.0, 0.95);
    const double inflation = (1.0 + rho) / (1.0 - rho);
    h.effective_n = std::max(2.0, h.residuals / inflation);
    double sum = 0;
    for (const double r : residuals) sum += r;
    h.mean = sum / h.residuals;
    const double day = model.day_mean_sigma * std::sqrt(24.0 / std::max(options.window_h, 24.0));
    h.drift_z = h.mean / std::max(day, s / std::sqrt(h.effective_n));
    h.drift_critical = model.cv_days > 0 ? registration::student_t_quantile(
                                               1.0 - 0.5 * options.alpha, model.cv_days)
                                         : registration::normal_quantile(1.0 - 0.5 * options.alpha);
    h.drifted = std::abs(h.drift_z) > h.drift_critical;
    std::vector<double> centred(residuals);
    for (double& r : centred) r -= h.mean;
    h.spread = kMadToSigma * median_and_mad(centred).mad;
    h.spread_ratio = h.spread / s;
    const double dof = std::max(1.0, h.effective_n - 1.0);
    // day_spread_max is stored against the unfloored s.
    h.spread_critical =
        std::max(std::sqrt(registration::chi_square_quantile(1.0 - options.alpha, dof) / dof),
                 model.day_spread_max * model.prediction_sigma / s);
    h.spread_grew = h.spread_ratio > h.spread_critical;
    return h;
}

}  // namespace tlsmon::thermal
