#include "core/solar.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "core/angles.hpp"

namespace tlsmon {

double day_of_year(double unix_seconds) {
    using namespace std::chrono;
    const auto days =
        sys_days{} + std::chrono::days{static_cast<long>(std::floor(unix_seconds / 86400.0))};
    const year_month_day ymd{days};
    const sys_days first{ymd.year() / January / 1};
    return static_cast<double>((days - first).count() + 1);
}

SunPosition sun_position(double latitude_deg, double longitude_deg, double unix_seconds) {
    SunPosition s;
    const double utc_hours = std::fmod(std::fmod(unix_seconds / 3600.0, 24.0) + 24.0, 24.0);
    const double g = 2.0 * std::numbers::pi / 365.0 *
                     (day_of_year(unix_seconds) - 1.0 + (utc_hours - 12.0) / 24.0);
    const double eqtime_min = 229.18 * (0.000075 + 0.001868 * std::cos(g) - 0.032077 * std::sin(g) -
                                        0.014615 * std::cos(2 * g) - 0.040849 * std::sin(2 * g));
    const double decl = 0.006918 - 0.399912 * std::cos(g) + 0.070257 * std::sin(g) -
                        0.006758 * std::cos(2 * g) + 0.000907 * std::sin(2 * g) -
                        0.002697 * std::cos(3 * g) + 0.00148 * std::sin(3 * g);
    double solar_minutes = utc_hours * 60.0 + eqtime_min + 4.0 * longitude_deg;
    solar_minutes = std::fmod(std::fmod(solar_minutes, 1440.0) + 1440.0, 1440.0);
    s.solar_hour = solar_minutes / 60.0;
    s.declination_deg = decl / kDeg;
    const double omega = (s.solar_hour - 12.0) * 15.0 * kDeg;  // hour angle, west positive
    const double phi = latitude_deg * kDeg;
    const double sin_e =
        std::sin(phi) * std::sin(decl) + std::cos(phi) * std::cos(decl) * std::cos(omega);
    s.elevation_deg = std::asin(std::clamp(sin_e, -1.0, 1.0)) / kDeg;
    // cos e sin A = −cos δ sin ω; cos e cos A = sin δ cos φ − cos δ sin φ cos ω.
    const double east = -std::cos(decl) * std::sin(omega);
    const double north =
        std::sin(decl) * std::cos(phi) - std::cos(decl) * std::sin(phi) * std::cos(omega);
    s.azimuth_deg = std::fmod(std::atan2(east, north) / kDeg + 360.0, 360.0);
    return s;
}

double sunrise_solar_hour(double latitude_deg, double declination_deg) {
    const double phi = latitude_deg * kDeg, decl = declination_deg * kDeg;
    const double c = (std::sin(-0.833 * kDeg) - std::sin(phi) * std::sin(decl)) /
                     (std::cos(phi) * std::cos(decl));
    if (c <= -1.0) return 0.0;  // the sun never sets
    if (c >= 1.0) return 12.0;  // it never rises
    return 12.0 - std::acos(c) / kDeg / 15.0;
}

std::array<double, 4> clear_sky_face_irradiance(const SunPosition& sun) {
    std::array<double, 4> out{};
    if (sun.elevation_deg <= 0.0) return out;
    const double e = sun.elevation_deg * kDeg, a = sun.azimuth_deg * kDeg;
    const double am =
        1.0 / (std::sin(e) + 0.50572 * std::pow(sun.elevation_deg + 6.07995, -1.6364));
    const double dni = 1353.0 * std::pow(0.7, std::pow(am, 0.678));
    const double diffuse = 0.5 * 0.1 * dni * std::sin(e);
    const double east = std::cos(e) * std::sin(a), north = std::cos(e) * std::cos(a);
    const std::array<double, 4> cos_incidence = {-east, east, -north, north};
    for (int f = 0; f < 4; ++f) out[f] = dni * std::max(0.0, cos_incidence[f]) + diffuse;
    return out;
}

double lag_step(double y, double x0, double x1, double h, double tau) {
    if (tau <= 0.0) return x1;
    const double e = std::exp(-h / tau);
    const double slope_tau = (x1 - x0) / h * tau;
    return x1 - slope_tau + (y - x0 + slope_tau) * e;
}

}  // namespace tlsmon
