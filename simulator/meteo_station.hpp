#pragma once
// The site's weather station: what it logs beside each scan, `<scan stem>.meteo.csv`
// (format in docs/formats.md, "Meteo sidecar"). One reading a minute from `span_minutes`
// before the acquisition time to the acquisition time itself; each reading is the scene's
// air (weather.hpp) plus the sensor's Gaussian noise, seeded by the weather seed and the
// reading's time (the same minute reads the same in every file), rounded to 0.1.
#include <cstdint>
#include <string>
#include <vector>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct MeteoReading {
    std::int64_t utc = 0;
    double temperature_c = 0.0;
    double pressure_hpa = 0.0;
    double relative_humidity_pct = 0.0;
};

// The readings of the file for a scan acquired at `acquired_utc`, oldest first.
std::vector<MeteoReading> meteo_readings(const Site& site, std::int64_t acquired_utc);

// The file's text: a comment line, the header line, one row per reading.
std::string meteo_csv(const Site& site, std::int64_t acquired_utc);

}  // namespace tlsmon::sim
