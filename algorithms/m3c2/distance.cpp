#include "algorithms/m3c2/distance.hpp"

#include <cmath>

namespace tlsmon::m3c2 {

double sampling_sigma(const CylinderSide& reference, const CylinderSide& compared) {
    const double n1 = reference.count, n2 = compared.count;
    const double s1 = reference.spread, s2 = compared.spread;
    return std::sqrt(s1 * s1 / n1 + s2 * s2 / n2);
}

Distance distance_between(const CylinderSide& reference, const CylinderSide& compared,
                          const DistanceParameters& parameters) {
    Distance d;
    if (reference.count < parameters.min_points || compared.count < parameters.min_points) return d;
    if (!(reference.roughness <= parameters.max_reference_spread)) return d;
    if (std::isnan(reference.centre) || std::isnan(compared.centre)) return d;  // two surfaces
    d.distance = compared.centre - reference.centre;
    d.lod = 1.96 * (sampling_sigma(reference, compared) + parameters.registration_error);
    d.significant = std::abs(d.distance) > d.lod;
    return d;
}

}  // namespace tlsmon::m3c2
