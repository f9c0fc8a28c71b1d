#include "algorithms/m3c2/zone_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"

namespace tlsmon::m3c2 {

ZoneUncertainty zone_uncertainty(std::span<const double> sampling_sigma,
                                 std::span<const double> registration_sigma, double cylinder_radius,
                                 double core_spacing) {
    if (!(cylinder_radius > 0) || !(core_spacing > 0))
        throw Error("zone uncertainty: the cylinder radius and the core spacing must be > 0");
    return aggregate_uncertainty(
        sampling_sigma, registration_sigma,
        std::max(1.0, std::numbers::pi * cylinder_radius * cylinder_radius /
                          (core_spacing * core_spacing)));
}

ZoneUncertainty aggregate_uncertainty(std::span<const double> sampling_sigma,
                                      std::span<const double> registration_sigma, double overlap) {
    if (sampling_sigma.size() != registration_sigma.size())
        throw Error("zone uncertainty: " + std::to_string(sampling_sigma.size()) +
                    " sampling σ for " + std::to_string(registration_sigma.size()) +
                    " registration σ");
    if (!(overlap >= 1)) throw Error("zone uncertainty: the overlap must be >= 1");
    ZoneUncertainty u;
    u.n = sampling_sigma.size();
    if (u.n == 0) return u;
    double sum_s2 = 0, sum_reg = 0;
    for (std::size_t i = 0; i < u.n; ++i) {
        const double s = sampling_sigma[i], r = registration_sigma[i];
        if (!(s >= 0) || !(r >= 0) || !std::isfinite(s) || !std::isfinite(r))
            throw Error("zone uncertainty: core point " + std::to_string(i) +
                        " has a negative or non-finite σ");
        sum_s2 += s * s;
        sum_reg += r;
    }
    const double n = static_cast<double>(u.n);
    u.overlap = overlap;
    const double sampling_variance = u.overlap * (sum_s2 / n) / n;
    u.sampling_mean = std::sqrt(sampling_variance);
    u.registration = sum_reg / n;
    const double reg2 = u.registration * u.registration;
    u.mean_sigma = std::sqrt(sampling_variance + reg2);
    u.median_sigma = std::sqrt(std::numbers::pi / 2 * sampling_variance + reg2);
    return u;
}

}  // namespace tlsmon::m3c2
