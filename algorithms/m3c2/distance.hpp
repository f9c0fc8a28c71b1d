#pragma once
// The M3C2 distance and its level of detection at one core point (Lague 2013, eq. 1):
//   d = centre2 - centre1 (the compared cloud's statistic minus the reference's, positive
//       along the oriented normal),
//   LoD95 = 1.96 (sqrt(s1^2 / n1 + s2^2 / n2) + reg),
// significant when |d| > LoD95. With fewer than min_points in either cylinder there is no
// distance: NaN and not significant, never 0; likewise when the reference's roughness (its
// spread with the strays) exceeds max_reference_spread (not one surface) or when either cylinder
// holds two surfaces (its strays more than kMaxStrayShare of its points: a side without a centre,
// statistic_of).
#include <limits>

#include "algorithms/m3c2/cylinder.hpp"
#include "algorithms/m3c2/parameters.hpp"

namespace tlsmon::m3c2 {

struct Distance {
    double distance = std::numeric_limits<double>::quiet_NaN();
    double lod = std::numeric_limits<double>::quiet_NaN();  // LoD95
    bool significant = false;
};

// σ of the distance from the two cylinders' sampling: √(s1²/n1 + s2²/n2); NaN without one.
double sampling_sigma(const CylinderSide& reference, const CylinderSide& compared);

Distance distance_between(const CylinderSide& reference, const CylinderSide& compared,
                          const DistanceParameters& parameters);

}  // namespace tlsmon::m3c2
