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
#include <cstddef>
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

// At most one pair per reference keypoint, in the reference's order; an epoch keypoint may
// win for several reference keypoints unless `mutual` is set. Throws for positions that do
// not match the descriptors in number, or a non-positive radius or a ratio outside [0, 1].
std::vector<KeypointPair> match_keypoints(const std::vector<AngularPosition>& reference,
                                          const Descriptors& reference_descriptors,
                                          const std::vector<AngularPosition>& epoch,
                                          const Descriptors& epoch_descriptors,
                                          const MatchingParameters& parameters);

}  // namespace tlsmon::keypoints
