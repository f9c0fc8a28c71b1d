// The thermal model on the simulator's own zone displacement (no scans rendered): a zone's
// true change along its normal plus the M3C2 median's noise, the weather station's air at each
// epoch; trains on the first `days` and scores the next `days`. Prints the fit's time (the
// issue's 50 ms for 7 days of 672 epochs), the residual's RMS against the raw thermal swing,
// and the σ's coverage. Usage: bench_thermal_model [seed] [days] [noise_mm]
#include "algorithms/thermal/thermal_model.hpp"

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

}  // namespace

int main(int argc, char** argv) {
    const std::uint64_t seed = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 11;
    const int days = argc > 2 ? std::atoi(argv[2]) : 7;
    const double noise = (argc > 3 ? std::atof(argv[3]) : 0.15) * 1e-3;
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
    std::vector<double> zero(2);
    for (int e = 0; e < epochs; ++e) {
        const std::int64_t t = sim::kDefaultStartUtc + 900LL * e;
        const auto c = sim::epoch_conditions(site, e, e * 0.25, t);
        air.push_back({double(t), sim::meteo_readings(site, t).back().temperature_c});
        for (int f = 0; f < 2; ++f) {
            const double truth = face_median(site, faces[f], e, c.bending);
            if (e == 0) zero[f] = truth;
            obs[f].push_back({double(t), truth - zero[f] + noise * normal(rng), noise});
        }
    }
    thermal::ModelOptions options;
    options.drivers.location = {site.weather.latitude_deg, site.weather.longitude_deg};
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
        double sum2 = 0, lo = 1e9, hi = -1e9;
        int n = 0, covered = 0;
        for (std::size_t i = days * per_day; i < obs[f].size(); ++i) {
            if (!drivers[i].complete) continue;
            const auto pr = thermal::predict(*model, drivers[i], times[i], noise);
            const double r = obs[f][i].value - pr.value;
            sum2 += r * r;
            ++n;
            covered += std::abs(r) <= 1.96 * pr.sigma;
            lo = std::min(lo, obs[f][i].value);
            hi = std::max(hi, obs[f][i].value);
        }
        std::printf(
            "%s face, seed %llu: fit %.1f ms on %d epochs (lags %.1f h + %.1f h, s %.3f mm, "
            "rho %.2f, R2 %.4f, %d iterations); scored %d epochs: swing %.2f mm, residual RMS "
            "%.3f mm (%.1f %% of the swing), 95 %% coverage %.1f %%\n",
            faces[f].name, static_cast<unsigned long long>(seed), ms, model->observations,
            model->lags.surface_h, model->lags.section_h, model->residual_sigma * 1e3,
            model->lag1_autocorrelation, model->explained_share, model->iterations, n,
            (hi - lo) * 1e3, std::sqrt(sum2 / n) * 1e3, 100.0 * std::sqrt(sum2 / n) / (hi - lo),
            100.0 * covered / n);
    }
}
