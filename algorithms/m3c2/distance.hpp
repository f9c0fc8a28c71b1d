#pragma once
// The M3C2 distance and its level of detection at one core point (Lague 2013, eq. 1):
//   d = centre2 - centre1 (the compared cloud's statistic minus the reference's, positive
//       along the oriented normal),
//   LoD95 = 1.96 (sqrt(s1^2 / n1 + s2^2 / n2) + reg),
// significant when |d| > LoD95. With fewer than min_points in either cylinder there is no
// distance: NaN and not significant, never 0; likewise when the reference's roughness (its
// spread with the strays) exceeds max_reference_spread (not one surface) or when either cylinder
// holds two surfaces (its strays more than kMaxStrayShare of its points: a side without a centre,
// statistic_of); likewise when the compared cloud's points lie elsewhere in the cylinder than
// the reference's (partly_seen).
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

// The compared cloud saw part of what the reference saw in the cylinder (an occluder, the
// scan's window moved): the two points' mean offsets from the axis lie more than
// kMaxLateralShift of the reference's RMS distance from the axis apart. On relief the mean
// along the normal over part of the disc is not the mean over all of it, by up to the relief's
// size, repeated in every epoch and held by no σ (docs/m3c2.md, "An epoch that sees part of a
// cylinder"); where the normal is off by θ, a plane gives θ times the shift. A disc of radius R
// seen whole: offset 0, RMS distance R/√2; with a fifth of it (a segment) unseen the offset
// moves by about 0.2 R, 0.28 of it. Points drawn at random over the whole disc move it by
// s·√((1/n₁ + 1/n₂)/2) in each direction across the axis (s the RMS distance), so a shift is
// only taken for a part seen when it is also beyond kLateralChance of that (the 99.9 %
// quantile of χ² with 2 degrees of freedom, √13.8): a sparse cylinder's cannot tell.
inline constexpr double kMaxLateralShift = 0.2;
inline constexpr double kLateralChance = 3.72;
bool partly_seen(const CylinderSide& reference, const CylinderSide& compared);

Distance distance_between(const CylinderSide& reference, const CylinderSide& compared,
                          const DistanceParameters& parameters);

}  // namespace tlsmon::m3c2
