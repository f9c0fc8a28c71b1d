// The weather station's sidecar file: the agreed layout (comment, header, one row a minute
// from five minutes before the scan to its acquisition time, 0.1 resolution) and values
// that match the truth's air within the station's noise and resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "simulator/series.hpp"
#include "simulator/truth.hpp"

namespace tlsmon::sim {
namespace {

constexpr std::int64_t kStart = 1780293600;  // 2026-06-01T06:00:00Z

struct Row {
    std::string time;
    std::string t, p, rh;
};

std::vector<Row> rows(const std::string& csv, std::string& header) {
    std::istringstream in(csv);
    std::string line;
    std::vector<Row> out;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        if (header.empty()) {
            header = line;
            continue;
        }
        Row r;
        std::istringstream f(line);
        std::getline(f, r.time, ',');
        std::getline(f, r.t, ',');
        std::getline(f, r.p, ',');
        std::getline(f, r.rh, ',');
        out.push_back(r);
    }
    return out;
}

// "14.2": one decimal exactly (the station's resolution).
bool one_decimal(const std::string& v) {
    const auto dot = v.find('.');
    return dot != std::string::npos && dot + 2 == v.size();
}

void expect_matches_truth(const Site& s, int epoch, double tolerance) {
    const EpochFiles f = simulate_epoch(s, epoch, kStart, 2);
    std::string header;
    const std::vector<Row> r = rows(f.meteo, header);
    EXPECT_EQ(f.meteo.rfind("# ", 0), 0u);  // a comment line first
    EXPECT_EQ(header, "time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct");
    ASSERT_EQ(r.size(), 6u);  // 5 min before the scan to the scan, one a minute
    for (std::size_t k = 0; k < r.size(); ++k) {
        const std::int64_t t = f.acquired_utc - 60 * static_cast<std::int64_t>(5 - k);
        EXPECT_EQ(r[k].time, format_utc(t));
        EXPECT_TRUE(one_decimal(r[k].t) && one_decimal(r[k].p) && one_decimal(r[k].rh))
            << r[k].t << " " << r[k].p << " " << r[k].rh;
        // The truth's air at the reading's time.
        const auto w = truth_json(s, epoch, 0.0, t, nullptr)["weather"];
        EXPECT_NEAR(std::stod(r[k].t), w["air_temperature_c"].get<double>(), tolerance);
        EXPECT_NEAR(std::stod(r[k].p), w["pressure_hpa"].get<double>(), tolerance);
        EXPECT_NEAR(std::stod(r[k].rh), w["relative_humidity_pct"].get<double>(), tolerance);
    }
    // The last reading is at the acquisition time, where the epoch's truth reports the air.
    EXPECT_NEAR(std::stod(r.back().t), f.truth["weather"]["air_temperature_c"].get<double>(),
                tolerance);
    EXPECT_EQ(f.truth["meteo_station"]["file"], f.stem + ".meteo.csv");
}

TEST(SimulatorMeteoStation, ReadingsMatchTheTruthWithinTheResolution) {
    Site s = preset_small();
    s.meteo.temperature_sigma_c = 0.0;
    s.meteo.pressure_sigma_hpa = 0.0;
    s.meteo.humidity_sigma_pct = 0.0;
    s.events.missing_epochs = {7};  // the truth and the meteo only, no render
    // Without sensor noise: within half the 0.1 resolution.
    expect_matches_truth(s, 7, 0.05 + 1e-9);
}

TEST(SimulatorMeteoStation, ReadingsMatchTheTruthWithinTheSensorNoise) {
    Site s = preset_small();
    s.events.missing_epochs = {9};
    // σ = 0.1 per quantity: within 5σ plus half the resolution (18 values).
    expect_matches_truth(s, 9, 0.55);
}

TEST(SimulatorMeteoStation, LogsForAMissingScanAndCanBeSwitchedOff) {
    Site s = preset_small();
    s.events.missing_epochs = {2};
    EXPECT_FALSE(simulate_epoch(s, 2, kStart, 2).meteo.empty());
    s.meteo.enabled = false;
    const EpochFiles off = simulate_epoch(s, 2, kStart, 2);
    EXPECT_TRUE(off.meteo.empty());
    EXPECT_TRUE(off.truth["meteo_station"]["file"].is_null());
}

}  // namespace
}  // namespace tlsmon::sim
