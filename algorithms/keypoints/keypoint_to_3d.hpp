#pragma once
// Matched keypoints back to 3-D (Hochmoselbrücke method, step 4): the range, azimuth and
// elevation images bilinearly interpolated at the keypoint's sub-pixel position give its
// polar coordinates in the scanner frame, d(φ, e) · r the point, and the scanner -> project
// transform (the scan's pose, then the epoch's registration) the point in the project
// frame. A keypoint is dropped when one of the four pixels around it has no return, or when
// the four straddle a depth edge: interpolating across an edge gives a point on neither
// surface.
#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <vector>

#include "algorithms/keypoints/features.hpp"
#include "algorithms/keypoints/keypoint_match.hpp"
#include "algorithms/keypoints/keypoint_matching.hpp"
#include "algorithms/keypoints/spherical_image.hpp"

namespace tlsmon::keypoints {

struct DepthEdge {
    // The four ranges straddle an edge when max − min exceeds
    // max(absolute, relative · their mean). The relative part leaves grazing surfaces,
    // whose neighbouring ranges differ by r · step · tan(incidence), their keypoints.
    double absolute = 0.05;  // m
    double relative = 0.02;
};

// The polar coordinates at (row, column), or nothing (an empty neighbour, outside the
// image, or a depth edge).
enum class Dropped { no, outside, empty_neighbour, depth_edge };
struct PolarAt {
    Polar polar;
    Dropped dropped = Dropped::no;
};
PolarAt polar_at(const SphericalImages& images, double row, double column,
                 const DepthEdge& edge = {});

// How many pairs went no further, and why.
struct DroppedCounts {
    std::size_t dropped_outside = 0, dropped_empty_neighbour = 0, dropped_depth_edge = 0;
    // Counts `d` under its reason; false when nothing was dropped (Dropped::no).
    bool count(Dropped d);
};

struct MatchesIn3d : DroppedCounts {
    std::vector<KeypointMatch> matches;  // segment −1: assigned later
};

// The polar part of a match: both epochs' ranges and angles, the epoch's azimuth brought
// within π of the reference's (two images may unwrap azimuths differently).
void set_polar(KeypointMatch& m, const Polar& reference, const Polar& epoch);

// One KeypointMatch per pair that both images can take to 3-D. `*_to_project`: the
// scanner -> project transform of each scan (for a scan read with pose P and registered
// with T: T · P).
MatchesIn3d matches_to_3d(const SphericalImages& reference_images,
                          const std::vector<Keypoint>& reference_keypoints,
                          const Eigen::Affine3d& reference_to_project,
                          const SphericalImages& epoch_images,
                          const std::vector<Keypoint>& epoch_keypoints,
                          const Eigen::Affine3d& epoch_to_project,
                          const std::vector<KeypointPair>& pairs, const DepthEdge& edge = {});

}  // namespace tlsmon::keypoints
