#pragma once
// The atmosphere between the scanner and the scene: a phase-based rangefinder converts time
// of flight to range with the group refractive index of its atmospheric setting; the light
// travels at c/n_true. Every range is therefore measured as
//   r_measured = r_true · n_true / n_setting      (≈ −0.93 ppm/°C, +0.27 ppm/hPa at 20 °C)
// with the group refractivity of air from the IAG resolution of 1999 (Rüeger 1999/2002,
// "Refractive indices of light, infrared and radio waves in the atmosphere", IAG Special
// Commission SC3; the closed formula adopted at the IUGG General Assembly in Birmingham):
//   N_gr   = 287.6155 + 4.88660/λ² + 0.06800/λ⁴    standard air (0 °C, 1013.25 hPa, dry,
//                                                   375 ppm CO₂), λ in µm
//   N_L    = (273.15/1013.25) · N_gr · p/T − 11.27 · e/T   T in K, p and e in hPa
//   e      = RH/100 · f · E_w(t),  E_w = 6.1121 · exp(17.502 t/(240.97 + t))  (Buck 1981),
//   f      = 1.0007 + 3.46e-6 · p                   enhancement factor (Buck 1981)
// n = 1 + N·1e-6. The formula itself is in core/group_refractivity.hpp.
#include "simulator/scene.hpp"
#include "simulator/weather.hpp"

namespace tlsmon::sim {

// E_w over water, hPa, t in °C (Buck 1981), without the enhancement factor.
double saturation_vapour_pressure_hpa(double t_c);

// N_gr of standard air at `wavelength_nm`.
double standard_group_refractivity(double wavelength_nm);

// N_L of air at temperature, pressure and relative humidity.
double group_refractivity(double wavelength_nm, double t_c, double p_hpa, double rh_pct);

struct AtmosphereEffect {
    double refractivity_setting = 0.0;  // N of the scanner's setting
    double refractivity_true = 0.0;     // N of the scene's air
    double range_scale = 1.0;           // n_true / n_setting (1 when disabled)
    double ppm = 0.0;                   // (range_scale − 1) · 1e6
};
AtmosphereEffect atmosphere_effect(const Atmosphere& a, const AirSample& air);

}  // namespace tlsmon::sim
