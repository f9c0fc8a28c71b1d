// The site's weather and the pier's thermal bending, read from the truth over a few
// simulated days: the air's daily cycle has its minimum at dawn and its maximum in the
// afternoon, the sun stands where the almanac puts it, the section temperatures obey their
// first-order lag, and the pier's top follows the lagged temperature difference, its daily
// maximum coming after the driving difference's by about the lag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "simulator/series.hpp"
#include "simulator/truth.hpp"

namespace tlsmon::sim {
namespace {

constexpr std::int64_t kMidnight = 1780272000;  // 2026-06-01T00:00:00Z
constexpr double kCadenceHours = 0.25;

// The truth (no scan rendered) every 15 min for `days` days from midnight UTC.
std::vector<nlohmann::json> truth_series(const Site& s, int days) {
    std::vector<nlohmann::json> out;
    for (int k = 0; k < days * 96; ++k) {
        out.push_back(truth_json(s, k, k * kCadenceHours, kMidnight + k * 900, nullptr));
    }
    return out;
}

double num(const nlohmann::json& j) {
    return j.get<double>();
}

// Index ranges [begin, end) of whole local solar days (solar_hour wraps at midnight).
std::vector<std::pair<std::size_t, std::size_t>> solar_days(const std::vector<nlohmann::json>& t) {
    std::vector<std::size_t> starts;
    for (std::size_t i = 1; i < t.size(); ++i) {
        if (num(t[i]["weather"]["solar_hour"]) < num(t[i - 1]["weather"]["solar_hour"]))
            starts.push_back(i);
    }
    std::vector<std::pair<std::size_t, std::size_t>> days;
    for (std::size_t k = 0; k + 1 < starts.size(); ++k) days.push_back({starts[k], starts[k + 1]});
    return days;
}

TEST(SimulatorWeather, AirIsColdestAtDawnAndWarmestInTheAfternoon) {
    const Site s = preset_small();
    const auto t = truth_series(s, 5);
    const auto days = solar_days(t);
    ASSERT_EQ(days.size(), 4u);
    std::vector<double> maxima;
    for (const auto& [b, e] : days) {
        std::size_t lo = b, hi = b, sunrise = 0;
        double sun_max = -90.0;
        for (std::size_t i = b; i < e; ++i) {
            const auto& w = t[i]["weather"];
            if (num(w["air_temperature_c"]) < num(t[lo]["weather"]["air_temperature_c"])) lo = i;
            if (num(w["air_temperature_c"]) > num(t[hi]["weather"]["air_temperature_c"])) hi = i;
            // Sunrise: the upper limb with refraction at the horizon, elevation −0.833°.
            if (!sunrise && num(w["sun_elevation_deg"]) > -0.833) sunrise = i;
            sun_max = std::max(sun_max, num(w["sun_elevation_deg"]));
        }
        const double h_sunrise = num(t[sunrise]["weather"]["solar_hour"]);
        const double h_min = num(t[lo]["weather"]["solar_hour"]);
        const double h_max = num(t[hi]["weather"]["solar_hour"]);
        // The almanac: sunrise at 49.97° N in early June ≈ 4:00 local solar time.
        EXPECT_NEAR(h_sunrise, 4.0, 0.35);
        // The minimum at dawn (within an hour: the mid-range temperature drifts from day to
        // day, which moves the minimum by a few sampling steps), the maximum mid-afternoon.
        EXPECT_NEAR(h_min, h_sunrise, 1.0) << "day starting at epoch " << b;
        EXPECT_GE(h_max, 13.5) << "day starting at epoch " << b;
        EXPECT_LE(h_max, 16.5) << "day starting at epoch " << b;
        // Noon elevation 90° − φ + δ, δ ≈ +22.0..22.3° on 1–5 June.
        EXPECT_NEAR(sun_max, 90.0 - 49.97 + 22.15, 0.5);
        maxima.push_back(num(t[hi]["weather"]["air_temperature_c"]));
        // Relative humidity is higher at the cool dawn than in the warm afternoon.
        EXPECT_GT(num(t[lo]["weather"]["relative_humidity_pct"]),
                  num(t[hi]["weather"]["relative_humidity_pct"]) + 5.0);
    }
    // Day-to-day variation: the daily maxima are not all the same.
    const auto [mn, mx] = std::minmax_element(maxima.begin(), maxima.end());
    EXPECT_GT(*mx - *mn, 0.3);
    // Plausible air throughout.
    for (const auto& j : t) {
        const auto& w = j["weather"];
        EXPECT_GT(num(w["air_temperature_c"]), -10.0);
        EXPECT_LT(num(w["air_temperature_c"]), 40.0);
        EXPECT_GT(num(w["pressure_hpa"]), 960.0);
        EXPECT_LT(num(w["pressure_hpa"]), 1060.0);
        EXPECT_GE(num(w["relative_humidity_pct"]), 5.0);
        EXPECT_LE(num(w["relative_humidity_pct"]), 100.0);
    }
}

// The state at a time does not depend on the epoch number or the series start: an epoch
// rendered alone gives the same weather and bending as in its series.
TEST(SimulatorWeather, AnEpochAloneHasTheSameWeatherAsInItsSeries) {
    const Site s = preset_small();
    const std::int64_t t = kMidnight + 15 * 3600;
    const auto a = truth_json(s, 60, 15.0, t, nullptr);
    const auto b = truth_json(s, 0, 0.0, t, nullptr);
    EXPECT_EQ(a["weather"].dump(), b["weather"].dump());
    EXPECT_EQ(a["deformation"].dump(), b["deformation"].dump());
    EXPECT_EQ(a["atmosphere"].dump(), b["atmosphere"].dump());
}

TEST(SimulatorWeather, BendingFollowsTheLaggedTemperatureDifference) {
    const Site s = preset_small();
    const auto t = truth_series(s, 4);
    const double alpha = s.deformation.expansion_coefficient;
    const double tau = s.deformation.time_constant_hours;
    const double h = s.pier.height;
    const double bx = s.pier.x1 - s.pier.x0, by = s.pier.y1 - s.pier.y0;
    double largest = 0.0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        const auto& d = t[i]["deformation"];
        const auto& faces = t[i]["weather"]["faces"];
        const auto side = [&](const char* f) { return num(faces[f]["section_temperature_c"]); };
        const auto face = [&](const char* f) { return num(faces[f]["temperature_c"]); };
        // ΔT across the section: x west − east, y south − north (the top moves away from the
        // warmer side).
        const double dx = side("west") - side("east"), dy = side("south") - side("north");
        ASSERT_NEAR(num(d["delta_t_lagged_c"][0]), dx, 1e-12);
        ASSERT_NEAR(num(d["delta_t_lagged_c"][1]), dy, 1e-12);
        ASSERT_NEAR(num(d["delta_t_driving_c"][1]), face("south") - face("north"), 1e-12);
        // u_top = κ H²/2, κ = α ΔT / b; u_z,top = α (T̄ − T_ref) H.
        const double mean = 0.25 * (side("west") + side("east") + side("south") + side("north"));
        const Eigen::Vector3d top(0.5 * alpha * dx / bx * h * h, 0.5 * alpha * dy / by * h * h,
                                  alpha * (mean - s.deformation.reference_temperature_c) * h);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(num(d["top_displacement_m"][k]), top[k], 1e-12);
        for (const auto& sample : t[i]["samples"]) {
            if (sample["name"] != "top_centre") continue;
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(num(sample["displacement"][k]), top[k], 1e-12);
        }
        largest = std::max(largest, top.head<2>().norm());
        // The lag: dS/dt = (F − S)/τ for every side S behind its face F, checked by central
        // differences over ±15 min (error ~ Δt²/6 · S''' ≈ 0.01 K/h for these curves).
        if (i == 0 || i + 1 == t.size()) continue;
        for (const char* f : kFaceNames) {
            const double ds = (num(t[i + 1]["weather"]["faces"][f]["section_temperature_c"]) -
                               num(t[i - 1]["weather"]["faces"][f]["section_temperature_c"])) /
                              (2.0 * kCadenceHours);
            ASSERT_NEAR(ds, (face(f) - side(f)) / tau, 0.05) << f << " at epoch " << i;
        }
    }
    // A sunny June day bends the 40 m pier by several millimetres at the top.
    EXPECT_GT(largest, 0.005);

    // Each day the top's y displacement peaks after the driving ΔT_y (the south face in the
    // midday sun). A first-order lag's output peaks where it meets its input, and for a
    // sinusoid of period P that is arctan(2πτ/P)/(2π/P) after the input's peak: 2.5 h for
    // the 24 h fundamental and 1.9 h for the 12 h harmonic with τ = 3 h, always below τ.
    // The daily bump lies between those periods: the delay is within [0.6 τ, τ] up to one
    // 15 min sampling step either side.
    for (const auto& [b, e] : solar_days(t)) {
        std::size_t drive = b, top = b;
        for (std::size_t i = b; i < e; ++i) {
            if (num(t[i]["deformation"]["delta_t_driving_c"][1]) >
                num(t[drive]["deformation"]["delta_t_driving_c"][1]))
                drive = i;
            if (num(t[i]["deformation"]["top_displacement_m"][1]) >
                num(t[top]["deformation"]["top_displacement_m"][1]))
                top = i;
        }
        const double delay =
            (static_cast<double>(top) - static_cast<double>(drive)) * kCadenceHours;
        std::cout << "day from epoch " << b << ": driving ΔT_y peaks at epoch " << drive
                  << ", the top's y displacement at " << top << ": " << delay << " h later\n";
        EXPECT_GE(delay, 0.6 * tau - kCadenceHours) << "day starting at epoch " << b;
        EXPECT_LE(delay, tau + kCadenceHours) << "day starting at epoch " << b;
    }
}

}  // namespace
}  // namespace tlsmon::sim
