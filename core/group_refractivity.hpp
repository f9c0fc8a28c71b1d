#pragma once
// The group refractivity of air for a phase-based rangefinder, and the range scale between
// a scanner's atmospheric setting and the actual air, shared by the simulator (which makes
// the error) and the registration (which corrects it). IAG resolution of 1999 (Rüeger
// 1999/2002, "Refractive indices of light, infrared and radio waves in the atmosphere", IAG
// Special Commission SC3):
//   N_gr = 287.6155 + 4.88660/λ² + 0.06800/λ⁴      standard air (0 °C, 1013.25 hPa, dry,
//                                                  375 ppm CO₂), λ in µm
//   N_L  = (273.15/1013.25) · N_gr · p/T − 11.27 · e/T   T in K, p and e in hPa
//   e    = RH/100 · f · E_w(t),  E_w = 6.1121 · exp(17.502 t/(240.97 + t))  (Buck 1981),
//   f    = 1.0007 + 3.46e-6 · p                     enhancement factor (Buck 1981)
// n = 1 + N·1e-6. A range converted with the setting's index is measured as
//   r_measured = r_true · n_true / n_setting.
namespace tlsmon {

// E_w over water, hPa, t in °C (Buck 1981), without the enhancement factor.
double saturation_vapour_pressure_hpa(double t_c);

// N_gr of standard air at `wavelength_nm`.
double standard_group_refractivity(double wavelength_nm);

// N_L of air at temperature (°C), pressure (hPa) and relative humidity (%).
double group_refractivity(double wavelength_nm, double t_c, double p_hpa, double rh_pct);

// n_true / n_setting from the two refractivities: r_measured = r_true · range_scale.
inline double range_scale(double refractivity_true, double refractivity_setting) {
    return (1.0 + refractivity_true * 1e-6) / (1.0 + refractivity_setting * 1e-6);
}

}  // namespace tlsmon
