#pragma once
// Is the thermal model still the structure's? (docs/thermal.md, "Model health"). Over a
// trailing window of W hours holding n compensated residuals r_i, with the model's
// out-of-sample σ s (never below the training's measurement σ: residual_reference_sigma), the RMS
// σ_day of its left-out days' mean residuals and the lag-1 autocorrelation ρ of its training
// residuals:
//   drift:  z = r̄ / σ_r̄,  σ_r̄ = max(σ_day·√(24 h / W), s·√((1 + ρ)/((1 − ρ)·n))) — a day's
//           mean strays by what the model misses that day, not by s/√n — flagged when
//           |z| > t(k, 1 − α/2), Student's t with the k days σ_day was estimated from (the
//           normal quantile without them);
//   spread: the window's robust scale s_w (1.4826·MAD about r̄) against s, flagged when
//           s_w/s exceeds both √(χ²(ν, 1 − α)/ν), ν = n(1 − ρ)/(1 + ρ) − 1 effective degrees
//           of freedom, and the largest ratio a left-out training day reached (a day as unlike
//           the others as the training's most unusual one is no finding).
// A structure whose thermal behaviour changed (a bearing that seized, a crack that opened)
// leaves a daily cycle in the residuals: the spread grows; a structural step shifts the mean.
#include <vector>

#include "algorithms/thermal/thermal_model.hpp"

namespace tlsmon::thermal {

struct HealthOptions {
    int min_residuals = 24;  // fewer in the window: not judged
    double window_h = 24.0;  // the window's length
    double alpha = 0.001;    // of each test (two-sided for the drift)
};

struct ModelHealth {
    bool judged = false;  // enough residuals
    int residuals = 0;
    double effective_n = 0;
    double mean = 0;
    double drift_z = 0;
    double drift_critical = 0;
    double spread = 0;           // s_w
    double spread_ratio = 0;     // s_w / s
    double spread_critical = 0;  // the ratio's critical value √(χ²(ν, 1 − α)/ν)
    bool drifted = false;
    bool spread_grew = false;
};

ModelHealth model_health(const ThermalModel& model, const std::vector<double>& residuals,
                         const HealthOptions& options);

}  // namespace tlsmon::thermal
