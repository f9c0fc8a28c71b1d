#include "simulator/weather.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "simulator/atmosphere.hpp"
#include "simulator/random.hpp"

namespace tlsmon::sim {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr std::uint64_t kTemperatureStream = 0x74656d70ULL;
constexpr std::uint64_t kPressureStream = 0x70726573ULL;
constexpr std::uint64_t kCloudStream = 0x636c6f75ULL;
// Cloudiness is partly the negative of the pressure anomaly (lows bring clouds).
constexpr double kCloudPressureCorrelation = 0.5;

// Day d of a stationary AR(1) sequence x_d = φ x_{d−1} + √(1 − φ²) ε_d with unit variance,
// written as its moving average Σ φᵏ √(1 − φ²) ε_{d−k}, truncated where φᵏ < 1e-9: a pure
// function of the day number, so any day can be evaluated alone.
double ar1(std::uint64_t seed, std::uint64_t stream, std::int64_t day, double phi) {
    const double scale = std::sqrt(1.0 - phi * phi);
    const int terms =
        phi <= 0.0 ? 1 : static_cast<int>(std::ceil(std::log(1e-9) / std::log(phi))) + 1;
    double sum = 0.0, weight = 1.0;
    const std::uint64_t base = hash_combine(seed, stream);
    for (int k = 0; k < terms; ++k) {
        Rng rng(hash_combine(base, static_cast<std::uint64_t>(day - k)));
        sum += weight * rng.normal();
        weight *= phi;
    }
    return scale * sum;
}

// Daily values at local mean solar noon of day `day`.
struct DayValues {
    double mid_c = 0.0;             // M: mid-range temperature
    double cloudiness = 0.0;        // c
    double pressure_anomaly = 0.0;  // x_p, unit σ
};

DayValues day_values(const Weather& w, std::int64_t day) {
    const double phi = w.day_correlation;
    const double xt = ar1(w.seed, kTemperatureStream, day, phi);
    const double xp = ar1(w.seed, kPressureStream, day, phi);
    const double xc = ar1(w.seed, kCloudStream, day, phi);
    const double rho = kCloudPressureCorrelation;
    DayValues v;
    v.mid_c = w.mean_temperature_c + w.day_sigma_c * xt;
    v.cloudiness = std::clamp(
        w.cloudiness_mean + w.cloudiness_sigma * (-rho * xp + std::sqrt(1.0 - rho * rho) * xc), 0.0,
        1.0);
    v.pressure_anomaly = xp;
    return v;
}

// Day values interpolated between two noons; keeps the last pair (the spin-up asks for the
// same days thousands of times).
class DailyWeather {
  public:
    explicit DailyWeather(const Weather& w) : w_(&w) {}
    DayValues at(double unix_seconds) {
        // u is an integer at local mean solar noon.
        const double u = (unix_seconds + w_->longitude_deg / 15.0 * 3600.0) / 86400.0 - 0.5;
        const double d = std::floor(u);
        const auto day = static_cast<std::int64_t>(d);
        if (!valid_ || day != day_) {
            if (valid_ && day == day_ + 1) {
                a_ = b_;
            } else {
                a_ = day_values(*w_, day);
            }
            b_ = day_values(*w_, day + 1);
            day_ = day;
            valid_ = true;
        }
        const double s = 0.5 * (1.0 - std::cos(kPi * (u - d)));
        return {a_.mid_c + s * (b_.mid_c - a_.mid_c),
                a_.cloudiness + s * (b_.cloudiness - a_.cloudiness),
                a_.pressure_anomaly + s * (b_.pressure_anomaly - a_.pressure_anomaly)};
    }

  private:
    const Weather* w_;
    bool valid_ = false;
    std::int64_t day_ = 0;
    DayValues a_, b_;
};

// −1 at sunrise t_min, +1 at t_max, half-cosines between (hours of local solar time).
double daily_shape(double h, double t_min, double t_max) {
    if (h >= t_min && h <= t_max) return -std::cos(kPi * (h - t_min) / (t_max - t_min));
    const double since_max = h > t_max ? h - t_max : h + 24.0 - t_max;
    return std::cos(kPi * since_max / (t_min + 24.0 - t_max));
}

AirSample air_from(const Weather& w, const DayValues& day, const SunPosition& sun) {
    AirSample a;
    a.sun = sun;
    a.cloudiness = day.cloudiness;
    const double amplitude = 0.5 * w.daily_range_c * (1.0 - 0.6 * day.cloudiness);
    const double t_min = std::clamp(sunrise_solar_hour(w.latitude_deg, sun.declination_deg), 0.0,
                                    w.max_hour_solar - 2.0);
    a.temperature_c = day.mid_c + amplitude * daily_shape(sun.solar_hour, t_min, w.max_hour_solar);
    a.pressure_hpa = w.pressure_hpa + w.pressure_sigma_hpa * day.pressure_anomaly +
                     w.pressure_tide_hpa * std::cos(2.0 * kPi * (sun.solar_hour - 10.0) / 12.0);
    a.dew_point_c = day.mid_c - amplitude - (1.0 + 3.0 * (1.0 - day.cloudiness));
    a.relative_humidity_pct = std::clamp(100.0 * saturation_vapour_pressure_hpa(a.dew_point_c) /
                                             saturation_vapour_pressure_hpa(a.temperature_c),
                                         5.0, 100.0);
    return a;
}

// Face temperatures driven by the sun: T + a·I/h_o (sol-air temperature, ASHRAE Handbook of
// Fundamentals, ch. "Heat, air and moisture control", without the long-wave term).
std::array<double, 4> sol_air(const Weather& w, const AirSample& a,
                              const std::array<double, 4>& irradiance) {
    std::array<double, 4> t{};
    for (int f = 0; f < 4; ++f)
        t[f] = a.temperature_c + w.absorptance * irradiance[f] / w.surface_coefficient;
    return t;
}

}  // namespace

AirSample air_at(const Weather& w, double unix_seconds) {
    DailyWeather daily(w);
    return air_from(w, daily.at(unix_seconds),
                    sun_position(w.latitude_deg, w.longitude_deg, unix_seconds));
}

std::array<double, 4> face_irradiance(const SunPosition& sun, double cloudiness) {
    // Clouds: Kasten & Czeplak (1980), G = G_clear · (1 − 0.75 c^3.4), c the cloud cover.
    const double cloud = 1.0 - 0.75 * std::pow(cloudiness, 3.4);
    std::array<double, 4> out = clear_sky_face_irradiance(sun);
    for (double& i : out) i *= cloud;
    return out;
}

ThermalState thermal_state(const Site& site, double t) {
    const Weather& w = site.weather;
    const double tau_s = w.surface_time_constant_hours * 3600.0;
    const double tau = site.deformation.time_constant_hours * 3600.0;
    constexpr double step = 120.0;  // s; the lag update is exact for inputs linear per step
    const double spin_up = std::max(48.0 * 3600.0, 10.0 * (tau_s + tau));
    const auto steps = static_cast<long>(std::ceil(spin_up / step));

    DailyWeather daily(w);
    const auto sample = [&](double time, AirSample& air, std::array<double, 4>& irr) {
        air = air_from(w, daily.at(time), sun_position(w.latitude_deg, w.longitude_deg, time));
        irr = face_irradiance(air.sun, air.cloudiness);
        return sol_air(w, air, irr);
    };
    ThermalState s;
    std::array<double, 4> x = sample(t - steps * step, s.air, s.irradiance);
    s.face_c = x;  // start in equilibrium with the sol-air temperature
    s.section_c = x;
    for (long k = steps - 1; k >= 0; --k) {
        const std::array<double, 4> next = sample(t - k * step, s.air, s.irradiance);
        for (int f = 0; f < 4; ++f) {
            const double face = lag_step(s.face_c[f], x[f], next[f], step, tau_s);
            s.section_c[f] = lag_step(s.section_c[f], s.face_c[f], face, step, tau);
            s.face_c[f] = face;
        }
        x = next;
    }
    s.sol_air_c = x;
    if (s.air.sun.elevation_deg > 0.0) {
        s.sunlit_face = static_cast<int>(
            std::max_element(s.irradiance.begin(), s.irradiance.end()) - s.irradiance.begin());
    }
    return s;
}

}  // namespace tlsmon::sim
