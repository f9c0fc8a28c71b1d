#pragma once
// Which plane of an epoch is which plane of the reference with no approximate transformation
// (the datum-independent case: the scanner was knocked or set up anew), under the
// vertical-axis assumption — the scanner is levelled by its compensator, so the two frames
// differ by a rotation κ about z and a translation t:
//
// 1. Heading. Every pair (reference plane r, epoch plane e) whose normals have the same
//    elevation (|n_r,z − n_e,z| ≤ sin(max_angle)) and a horizontal part votes for
//        κ_re = atan2(n_r,y, n_r,x) − atan2(n_e,y, n_e,x);
//    the correlation of the two sets of normals peaks at the true κ (every pair of parallel
//    planes votes for it), and at κ ± 90° on a site of box-shaped faces, so the strongest
//    `heading_peaks` peaks are each tried.
// 2. Translation. Under Rz(κ), the pairs whose normals agree within `max_angle_deg` each give
//    one equation n_r·t = n_r·(c_r − Rz(κ)·c_e); three pairs with well-spread normals give t.
//    Hypotheses are drawn at random (a fixed seed: the same input gives the same answer) and
//    scored by the reference planes they explain one to one (misclosure along the normal
//    within `max_offset`, extents overlapping as in match_planes).
// 3. The best hypothesis's pairs are adjusted (adjust_planes, six parameters, so a residual
//    tilt of the standing axis is estimated as well): the approximate transformation from
//    which match_planes (the datum-dependent matching) and the congruence test proceed.
// Normals face their scanner in both frames (fit_plane's viewpoint), so only equal signs are
// paired: a re-set station does not cross a plane of the scene. A cloud without one scanner
// (a campaign's walk) has no side to turn its normals to: with `either_sign`, each epoch
// plane takes part with its normal and with the opposite one, and a pair takes the sign that
// agrees with the reference plane.
#include <cstddef>
#include <optional>
#include <span>

#include "algorithms/registration/plane_fit.hpp"
#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration {

struct PriorFreeMatchingParams {
    double max_angle_deg = 2.0;   // normals' agreement, and the levelling's tolerance
    double max_offset = 0.10;     // m, a mapped epoch centroid from its reference plane
    double overlap_factor = 2.0;  // as PlaneMatchingParams::overlap_factor
    std::size_t max_planes = 60;  // the largest planes of each list take part
    double min_horizontal = 0.3;  // |n_xy| of a normal that votes for the heading
    int heading_peaks = 4;        // heading candidates tried
    int hypotheses = 3000;        // translation hypotheses per heading
    std::size_t min_support = 4;  // reference planes explained, at least
    bool either_sign = false;     // the epoch's normals have no side (header)
};

struct PriorFreeMatch {
    RigidTransform approximate;  // the adjusted transformation on the supporting pairs
    double heading = 0.0;        // κ of the winning hypothesis, rad
    std::size_t support = 0;     // reference planes it explained
    std::size_t runner_up = 0;   // the best other heading's support (ambiguity)
};

// Nothing when no hypothesis explains `min_support` planes (too few planes, no vertical
// faces to fix the heading, or no three well-spread normals).
std::optional<PriorFreeMatch> match_planes_without_prior(
    std::span<const FittedPlane> reference, std::span<const FittedPlane> epoch,
    const PriorFreeMatchingParams& params = {});

}  // namespace tlsmon::registration
