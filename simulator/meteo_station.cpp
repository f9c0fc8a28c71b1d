#include "simulator/meteo_station.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "simulator/random.hpp"
#include "simulator/series.hpp"
#include "simulator/weather.hpp"

namespace tlsmon::sim {

namespace {

constexpr std::uint64_t kStationStream = 0x6d6574656fULL;

// To the station's 0.1 resolution; never "-0.0".
double resolve(double v) {
    return std::round(v * 10.0) / 10.0 + 0.0;
}

}  // namespace

std::vector<MeteoReading> meteo_readings(const Site& site, std::int64_t acquired_utc) {
    const MeteoStation& m = site.meteo;
    std::vector<MeteoReading> out;
    for (int k = m.span_minutes; k >= 0; --k) {
        const std::int64_t t = acquired_utc - 60LL * k;
        const AirSample air = air_at(site.weather, static_cast<double>(t));
        Rng rng(hash_combine(hash_combine(site.weather.seed, kStationStream),
                             static_cast<std::uint64_t>(t)));
        MeteoReading r;
        r.utc = t;
        r.temperature_c = resolve(air.temperature_c + m.temperature_sigma_c * rng.normal());
        r.pressure_hpa = resolve(air.pressure_hpa + m.pressure_sigma_hpa * rng.normal());
        r.relative_humidity_pct = resolve(std::clamp(
            air.relative_humidity_pct + m.humidity_sigma_pct * rng.normal(), 0.0, 100.0));
        out.push_back(r);
    }
    return out;
}

std::string meteo_csv(const Site& site, std::int64_t acquired_utc) {
    std::string text = "# tlsmon simulator: weather station of site '" + site.scanner.station +
                       "', one reading a minute\n";
    text += "time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct\n";
    char row[128];
    for (const MeteoReading& r : meteo_readings(site, acquired_utc)) {
        std::snprintf(row, sizeof row, "%s,%.1f,%.1f,%.1f\n", format_utc(r.utc).c_str(),
                      r.temperature_c, r.pressure_hpa, r.relative_humidity_pct);
        text += row;
    }
    return text;
}

}  // namespace tlsmon::sim
