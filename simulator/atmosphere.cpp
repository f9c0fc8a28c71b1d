#include "simulator/atmosphere.hpp"

#include <cmath>

namespace tlsmon::sim {

double saturation_vapour_pressure_hpa(double t_c) {
    return 6.1121 * std::exp(17.502 * t_c / (240.97 + t_c));
}

double standard_group_refractivity(double wavelength_nm) {
    const double l2 = (wavelength_nm * 1e-3) * (wavelength_nm * 1e-3);
    return 287.6155 + 4.88660 / l2 + 0.06800 / (l2 * l2);
}

double group_refractivity(double wavelength_nm, double t_c, double p_hpa, double rh_pct) {
    const double t_k = t_c + 273.15;
    const double e =
        rh_pct / 100.0 * (1.0007 + 3.46e-6 * p_hpa) * saturation_vapour_pressure_hpa(t_c);
    return 273.15 / 1013.25 * standard_group_refractivity(wavelength_nm) * p_hpa / t_k -
           11.27 * e / t_k;
}

AtmosphereEffect atmosphere_effect(const Atmosphere& a, const AirSample& air) {
    AtmosphereEffect out;
    out.refractivity_setting = group_refractivity(a.wavelength_nm, a.scanner_temperature_c,
                                                  a.scanner_pressure_hpa, a.scanner_humidity_pct);
    out.refractivity_true = group_refractivity(a.wavelength_nm, air.temperature_c, air.pressure_hpa,
                                               air.relative_humidity_pct);
    if (a.enabled) {
        out.range_scale =
            (1.0 + out.refractivity_true * 1e-6) / (1.0 + out.refractivity_setting * 1e-6);
        out.ppm = (out.range_scale - 1.0) * 1e6;
    }
    return out;
}

}  // namespace tlsmon::sim
