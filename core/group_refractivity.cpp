#include "core/group_refractivity.hpp"

#include <cmath>

namespace tlsmon {

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

}  // namespace tlsmon
