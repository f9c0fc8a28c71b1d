#include "simulator/atmosphere.hpp"

#include <cmath>

#include "core/group_refractivity.hpp"

namespace tlsmon::sim {

// The formula lives in core/group_refractivity.*, shared with the registration's correction.
double saturation_vapour_pressure_hpa(double t_c) {
    return tlsmon::saturation_vapour_pressure_hpa(t_c);
}

double standard_group_refractivity(double wavelength_nm) {
    return tlsmon::standard_group_refractivity(wavelength_nm);
}

double group_refractivity(double wavelength_nm, double t_c, double p_hpa, double rh_pct) {
    return tlsmon::group_refractivity(wavelength_nm, t_c, p_hpa, rh_pct);
}

AtmosphereEffect atmosphere_effect(const Atmosphere& a, const AirSample& air) {
    AtmosphereEffect out;
    out.refractivity_setting = group_refractivity(a.wavelength_nm, a.scanner_temperature_c,
                                                  a.scanner_pressure_hpa, a.scanner_humidity_pct);
    out.refractivity_true = group_refractivity(a.wavelength_nm, air.temperature_c, air.pressure_hpa,
                                               air.relative_humidity_pct);
    if (a.enabled) {
        out.range_scale = tlsmon::range_scale(out.refractivity_true, out.refractivity_setting);
        out.ppm = (out.range_scale - 1.0) * 1e6;
    }
    return out;
}

}  // namespace tlsmon::sim
