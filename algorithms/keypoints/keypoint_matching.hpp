#pragma once
// Matching the reference's keypoints in an epoch (Hochmoselbrücke method, step 3): the
// scanner stays on its station, so a surface point keeps nearly its angles; for each
// reference keypoint only the epoch's keypoints within a small angular radius are
// candidates, and the one with the nearest descriptor wins. Optionally (beyond the
// method) Lowe's ratio test among those candidates and a mutual check.
//
// Angles are the images' lattice angles at the keypoints' sub-pixel positions, and the
// radius is measured in them: √(Δφ² + Δe²), Δφ wrapped into (−π, π] — the images' own
// coordinates, in which the scanner's steps are the pixels.
//
// The window follows the range (docs/keypoints.md, "The matching window"): a displacement of
// w metres at range r turns the beam by w / r, so a fixed angle that suits a pier at 50 m is
// narrower than a 10 mm motion at 3 m and loses exactly the matches that moved most (a bias
// towards zero). Each reference keypoint's radius is the larger of the angle `window_radius`
// (the scanner's own orientation change, and the floor) and window_m / its range.
#include <cstddef>
#include <span>
#include <vector>

#include "algorithms/keypoints/features.hpp"
#include "algorithms/keypoints/parameters.hpp"
#include "algorithms/keypoints/spherical_image.hpp"

namespace tlsmon::keypoints {

struct AngularPosition {
    double azimuth = 0, elevation = 0;  // rad
};

// The lattice angles of each keypoint.
std::vector<AngularPosition> angular_positions(const SphericalImages& images,
                                               const std::vector<Keypoint>& keypoints);

struct MatchingParameters {
    double window_radius = Parameters{}.window_deg * 3.14159265358979323846 / 180.0;  // rad
    double window_m = Parameters{}.window_m;  // m at the object; 0: the angle alone
    // Lowe's ratio test: kept only when best < ratio · second best among the candidates
    // (a single candidate passes); 0 switches it off.
    double ratio = Parameters{}.ratio;
    // Kept only when the reference keypoint is also the epoch keypoint's best among the
    // reference keypoints within the radius.
    bool mutual = Parameters{}.mutual;
};

struct KeypointPair {
    std::size_t reference = 0;  // index into the reference's keypoints and descriptors
    std::size_t epoch = 0;      // index into the epoch's
    double distance = 0;        // descriptor distance (Hamming bits or Euclidean)
};

// Hamming distance (binary) or Euclidean distance (float) of descriptor i of a and j of b.
// Throws tlsmon::Error when the two sets differ in kind or length.
double descriptor_distance(const Descriptors& a, std::size_t i, const Descriptors& b,
                           std::size_t j);

// The angular window radius of a reference keypoint at `range` m: max(window_radius,
// window_m / range); the angle alone for a non-positive or non-finite range.
double window_radius_at(const MatchingParameters& parameters, double range);

// At most one pair per reference keypoint, in the reference's order; an epoch keypoint may
// win for several reference keypoints unless `mutual` is set. `reference_ranges` (m, one per
// reference keypoint; empty: the angle alone) widens each keypoint's window by window_m.
// Throws for positions that do not match the descriptors (or ranges) in number, a
// non-positive radius, a negative window_m or a ratio outside [0, 1].
std::vector<KeypointPair> match_keypoints(const std::vector<AngularPosition>& reference,
                                          const Descriptors& reference_descriptors,
                                          const std::vector<AngularPosition>& epoch,
                                          const Descriptors& epoch_descriptors,
                                          const MatchingParameters& parameters,
                                          std::span<const double> reference_ranges = {});

}  // namespace tlsmon::keypoints
