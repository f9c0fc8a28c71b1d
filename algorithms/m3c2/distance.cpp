#include "algorithms/m3c2/distance.hpp"

#include <algorithm>
#include <cmath>

namespace tlsmon::m3c2 {

double sampling_sigma(const CylinderSide& reference, const CylinderSide& compared) {
    const double n1 = reference.count, n2 = compared.count;
    const double s1 = reference.spread, s2 = compared.spread;
    return std::sqrt(s1 * s1 / n1 + s2 * s2 / n2);
}

bool partly_seen(const CylinderSide& reference, const CylinderSide& compared) {
    const double shift = (compared.lateral - reference.lateral).norm();
    const double chance = kLateralChance * std::sqrt(0.5 / reference.count + 0.5 / compared.count);
    // False where either is NaN.
    return shift > std::max(kMaxLateralShift, chance) * reference.lateral_spread;
}

Distance distance_between(const CylinderSide& reference, const CylinderSide& compared,
                          const DistanceParameters& parameters) {
    Distance d;
    if (reference.count < parameters.min_points || compared.count < parameters.min_points) return d;
    if (!(reference.roughness <= parameters.max_reference_spread)) return d;
    if (std::isnan(reference.centre) || std::isnan(compared.centre)) return d;  // two surfaces
    if (partly_seen(reference, compared)) return d;
    d.distance = compared.centre - reference.centre;
    d.lod = 1.96 * (sampling_sigma(reference, compared) + parameters.registration_error);
    d.significant = std::abs(d.distance) > d.lod;
    return d;
}

}  // namespace tlsmon::m3c2
