// The thermal model on the simulator's own zone displacement (no scans rendered): a zone's
// true change along its normal plus a measurement error, the weather station's air at each
// epoch; trains on the first `days` and scores the next `days`. Prints the fit's time (the
// issue's 50 ms for 7 days of 672 epochs), the residual's RMS against the raw thermal swing,
// and the σ's coverage; over a range of weather seeds also the coverage's spread from week to
// week. The measurement error is white (σ noise_mm) or, with correlation_h > 0, a first-order
// autoregressive one of that time constant (a registration's error that wanders over hours).
// Usage: bench_thermal_model [seed|first-last] [days] [noise_mm] [correlation_h]
#include "algorithms/thermal/thermal_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/statistics.hpp"
#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/meteo_station.hpp"
#include "simulator/scene.hpp"

using namespace tlsmon;

namespace {

struct Face {
    const char* name;
    Eigen::Vector3d normal;
    Eigen::Vector3d point;  // at z = 0 on the face, its middle
};

// The median over the face's height (0..H, uniform) of the true displacement along the normal.
double face_median(const sim::Site& site, const Face& f, int epoch, const sim::ThermalBending& b) {
    std::vector<double> v;
    for (int k = 0; k < 81; ++k) {
        Eigen::Vector3d p = f.point;
        p.z() = site.pier.height * k / 80.0;
        v.push_back(f.normal.dot(sim::pier_displacement(site, p, epoch, b)));
    }
    return median(v);
}

struct Score {
    double coverage = 0;                     // share of the scored epochs within 1.96 σ
    double rms = 0;                          // of the residual
    double sigma = 0;                        // RMS of the σ given
    int within[2] = {0, 0}, of[2] = {0, 0};  // in the training's amplitudes, extrapolated
};

// One weather seed: two faces' series, the model trained on the first `days`, the next scored.
std::vector<Score> score_seed(std::uint64_t seed, int days, double noise, double correlation_h) {
    sim::Site site = sim::preset_small();
    site.weather.seed = seed;
    const sim::Pier& p = site.pier;
    const Face faces[] = {{"south", {0, -1, 0}, {0.5 * (p.x0 + p.x1), p.y0, 0}},
                          {"west", {-1, 0, 0}, {p.x0, 0.5 * (p.y0 + p.y1), 0}}};
    const int per_day = 96;
    const int epochs = 2 * days * per_day;
    std::vector<thermal::AirReading> air;
    std::vector<std::vector<thermal::Observation>> obs(2);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    // AR(1) of stationary σ `noise`: e_k = φ e_{k−1} + √(1 − φ²)·noise·n_k.
    const double phi = correlation_h > 0 ? std::exp(-0.25 / correlation_h) : 0.0;
    std::vector<double> zero(2), error(2);
    for (int f = 0; f < 2; ++f) error[f] = noise * normal(rng);
    for (int e = 0; e < epochs; ++e) {
        const std::int64_t t = sim::kDefaultStartUtc + 900LL * e;
        const auto c = sim::epoch_conditions(site, e, e * 0.25, t);
        air.push_back({double(t), sim::meteo_readings(site, t).back().temperature_c});
        for (int f = 0; f < 2; ++f) {
            const double truth = face_median(site, faces[f], e, c.bending);
            if (e == 0) zero[f] = truth;
            if (e > 0) error[f] = phi * error[f] + std::sqrt(1 - phi * phi) * noise * normal(rng);
            obs[f].push_back({double(t), truth - zero[f] + error[f], noise});
        }
    }
    thermal::ModelOptions options;
    options.drivers.location = {site.weather.latitude_deg, site.weather.longitude_deg};
    std::vector<Score> scores;
    for (int f = 0; f < 2; ++f) {
        const std::vector<thermal::Observation> train(obs[f].begin(),
                                                      obs[f].begin() + days * per_day);
        std::string why;
        const auto t0 = std::chrono::steady_clock::now();
        const auto model = thermal::fit_thermal_model(air, train, options, why);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        if (!model) {
            std::printf("%s: no model: %s\n", faces[f].name, why.c_str());
            continue;
        }
        std::vector<double> times;
        for (const auto& o : obs[f]) times.push_back(o.t);
        const auto drivers = thermal::thermal_drivers(air, times, model->lags, options.drivers);
        double sum2 = 0, sigma2 = 0, lo = 1e9, hi = -1e9;
        int n = 0;
        Score s;
        for (std::size_t i = days * per_day; i < obs[f].size(); ++i) {
            if (!drivers[i].complete) continue;
            const auto pr = thermal::predict(*model, drivers[i], times[i], noise);
            const double r = obs[f][i].value - pr.value;
            sum2 += r * r;
            sigma2 += pr.sigma * pr.sigma;
            ++n;
            const bool beyond =
                thermal::far_beyond_training_amplitudes(*model, drivers[i].daily_amplitude_c);
            s.within[beyond] += std::abs(r) <= 1.96 * pr.sigma;
            ++s.of[beyond];
            lo = std::min(lo, obs[f][i].value);
            hi = std::max(hi, obs[f][i].value);
        }
        s.coverage = 100.0 * (s.within[0] + s.within[1]) / n;
        s.rms = std::sqrt(sum2 / n);
        s.sigma = std::sqrt(sigma2 / n);
        std::printf(
            "%s face, seed %llu: fit %.1f ms on %d epochs (lags %.1f h + %.1f h, s %.3f mm "
            "(in sample %.3f), rho %.2f, R2 %.4f, %d iterations); scored %d epochs: swing %.2f "
            "mm, residual RMS %.3f mm (%.1f %% of the swing), σ %.3f mm, 95 %% coverage %.1f "
            "%%\n",
            faces[f].name, static_cast<unsigned long long>(seed), ms, model->observations,
            model->lags.surface_h, model->lags.section_h, model->prediction_sigma * 1e3,
            model->residual_sigma * 1e3, model->lag1_autocorrelation, model->explained_share,
            model->iterations, n, (hi - lo) * 1e3, s.rms * 1e3, 100.0 * s.rms / (hi - lo),
            s.sigma * 1e3, s.coverage);
        scores.push_back(s);
    }
    return scores;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string seeds = argc > 1 ? argv[1] : "11";
    const auto dash = seeds.find('-');
    const std::uint64_t first = std::strtoull(seeds.c_str(), nullptr, 10);
    const std::uint64_t last =
        dash == std::string::npos ? first : std::strtoull(seeds.c_str() + dash + 1, nullptr, 10);
    const int days = argc > 2 ? std::atoi(argv[2]) : 7;
    const double noise = (argc > 3 ? std::atof(argv[3]) : 0.15) * 1e-3;
    const double correlation_h = argc > 4 ? std::atof(argv[4]) : 0.0;
    std::vector<double> coverage, ratio;
    int in_band = 0, within[2] = {0, 0}, of[2] = {0, 0};
    for (std::uint64_t seed = first; seed <= last; ++seed)
        for (const Score& s : score_seed(seed, days, noise, correlation_h)) {
            for (int k = 0; k < 2; ++k) within[k] += s.within[k], of[k] += s.of[k];
            coverage.push_back(s.coverage);
            ratio.push_back(s.rms / s.sigma);
            in_band += s.coverage >= 93.0 && s.coverage <= 98.0;
        }
    if (coverage.size() < 2) return 0;
    double mean = 0;
    for (const double c : coverage) mean += c;
    std::sort(coverage.begin(), coverage.end());
    std::sort(ratio.begin(), ratio.end());
    std::printf(
        "%zu scored weeks (seeds %llu-%llu, both faces): 95 %% coverage mean %.1f %%, min %.1f "
        "%%, median %.1f %%, max %.1f %%; %d of %zu within [93, 98] %%; residual RMS / σ median "
        "%.2f (min %.2f, max %.2f)\n",
        coverage.size(), static_cast<unsigned long long>(first),
        static_cast<unsigned long long>(last), mean / double(coverage.size()), coverage.front(),
        median(coverage), coverage.back(), in_band, coverage.size(), median(ratio), ratio.front(),
        ratio.back());
    std::printf(
        "  epochs within the training's daily amplitudes: %d, %.1f %% within the 95 %% "
        "bound; extrapolated: %d, %.1f %%\n",
        of[0], 100.0 * within[0] / std::max(1, of[0]), of[1],
        100.0 * within[1] / std::max(1, of[1]));
}
