#pragma once
// Which plane of an epoch is which plane of the reference, given an approximate
// transformation (the datum-dependent case: a fixed station, whose previous transformation or
// targets' registration is close): candidates are the reference planes whose normal lies
// within `max_angle_deg` of the mapped epoch normal, whose plane lies within `max_offset` of
// the mapped epoch centroid, and whose extent overlaps it; each pair is scored by the test
// statistic of its difference (plane_misclosure, plane_registration.hpp), and pairs are taken
// one to one, the best first. The congruence test (plane_registration.hpp) then finds what a
// wrong pair or a moved plane did to the adjustment.
#include <cstddef>
#include <span>
#include <vector>

#include "algorithms/registration/plane_fit.hpp"
#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration {

struct PlaneMatchingParams {
    double max_angle_deg = 1.0;  // between the normals after the approximate transformation
    double max_offset = 0.05;    // m, the mapped epoch centroid from the reference plane
    // The centroids' in-plane distance may be at most this many times the sum of the two
    // planes' RMS extents along it (a uniform patch reaches √3 ≈ 1.7 RMS from its centre).
    double overlap_factor = 2.0;
};

struct PlaneMatch {
    std::size_t reference = 0, epoch = 0;  // indices into the two lists
    double statistic = 0.0;  // wᵀ·Σ_ww⁻¹·w under the approximate transformation
};

// The pairs, by reference index.
std::vector<PlaneMatch> match_planes(std::span<const FittedPlane> reference,
                                     std::span<const FittedPlane> epoch,
                                     const RigidTransform& approximate,
                                     const PlaneMatchingParams& params = {});

}  // namespace tlsmon::registration
