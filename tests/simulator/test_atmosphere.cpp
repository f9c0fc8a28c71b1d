// The atmosphere: the group refractivity of the IAG 1999 formula at the scanner's
// wavelength, and every measured range carrying n_true / n_setting of the epoch's air.
#include <gtest/gtest.h>

#include <cmath>

#include "simulator/atmosphere.hpp"
#include "simulator/render.hpp"
#include "simulator/truth.hpp"

namespace tlsmon::sim {
namespace {

// Hand-evaluated from the IAG 1999 resolution (Rüeger) at λ = 1.5 µm:
// N_gr = 287.6155 + 4.88660/2.25 + 0.06800/5.0625 = 289.8008; at 20 °C, 1013.25 hPa,
// 60 % RH (e = 14.07 hPa): N = 289.8008 · 273.15/293.15 − 11.27 · 14.07/293.15 = 269.488.
TEST(SimulatorAtmosphere, GroupRefractivityFollowsTheIagFormula) {
    EXPECT_NEAR(standard_group_refractivity(1500.0), 289.8008, 1e-4);
    EXPECT_NEAR(group_refractivity(1500.0, 20.0, 1013.25, 60.0), 269.488, 1e-3);
    // The rules of thumb of EDM: about −1 ppm per °C and +0.27 ppm per hPa.
    const double n0 = group_refractivity(1500.0, 20.0, 1013.25, 60.0);
    EXPECT_NEAR(group_refractivity(1500.0, 21.0, 1013.25, 60.0) - n0, -0.95, 0.01);
    EXPECT_NEAR(group_refractivity(1500.0, 20.0, 1014.25, 60.0) - n0, 0.2665, 0.001);
    // The same air as the setting: no scale.
    Atmosphere a;
    AirSample air;
    air.temperature_c = a.scanner_temperature_c;
    air.pressure_hpa = a.scanner_pressure_hpa;
    air.relative_humidity_pct = a.scanner_humidity_pct;
    EXPECT_EQ(atmosphere_effect(a, air).ppm, 0.0);
    air.temperature_c += 10.0;  // air warmer than set: light faster, ranges read short
    EXPECT_NEAR(atmosphere_effect(a, air).ppm, -9.3, 0.3);
}

// Noise, drift, footprint and bending off: a range to the flat south face differs from the
// analytic range by exactly the truth's ppm. The setting is 0 °C, the air near 18 °C: the
// light is faster than the scanner assumes and the ranges read short (≈ −20 ppm, ≈ −1 mm
// at 50 m).
TEST(SimulatorAtmosphere, MeasuredRangesCarryTheTruthsPpm) {
    Site s = preset_small();
    s.noise.enabled = false;
    s.drift.enabled = false;
    s.deformation.enabled = false;
    s.beam.footprint = false;
    s.atmosphere.scanner_temperature_c = 0.0;
    const std::int64_t utc = kDefaultStartUtc + 8 * 3600;
    const auto truth = truth_json(s, 32, 8.0, utc, nullptr);
    const double ppm = truth["atmosphere"]["range_ppm"].get<double>();
    EXPECT_LT(ppm, -10.0);
    const Scan scan = render_epoch(s, epoch_conditions(s, 32, 8.0, utc)).scan;
    const Eigen::Vector3d o = s.scanner.position;
    std::size_t n = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Vector3d& p = scan.xyz[i];
        if (p.z() < 1.0 || p.x() < s.pier.x0 + 0.5 || p.x() > s.pier.x1 - 0.5) continue;
        if (std::abs(p.y() - s.pier.y0) > 0.01) continue;  // the south face y = y0
        const double el = cell_elevation(s.scanner, scan.grid->row[i]);
        const double az = cell_azimuth(s.scanner, scan.grid->column[i]);
        const double dy = std::cos(el) * std::sin(az);
        const double r_true = (s.pier.y0 - o.y()) / dy;
        const double measured = ((p - o).norm() / r_true - 1.0) * 1e6;
        worst = std::max(worst, std::abs(measured - ppm));
        ++n;
    }
    EXPECT_GT(n, 30'000u);
    EXPECT_LT(worst, 0.05);
}

}  // namespace
}  // namespace tlsmon::sim
