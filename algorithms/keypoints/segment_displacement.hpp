#pragma once
// Step 6 of the keypoint method (Hochmoselbrücke case study): the displacement of one
// segment — a configured zone, or a band of the vertical angle — from the matches the
// outlier filters kept. Definitions (docs/keypoints.md, pinned by
// tests/algorithms/test_keypoint_segments.cpp):
// - At least `min_matches` (default 10) kept matches, else the segment is undefined: its
//   figures are NaN and `defined()` is false, with the reason in `undefined_reason`.
// - mean: the mean displacement vector (project frame, m); std_dev: the sample standard
//   deviation (n − 1) of each component; standard_error: the kept mean's as a trimmed mean's,
//   from the Winsorized values of every match of the segment (a removed value set to the
//   nearest kept extreme), clustered by `cluster_px` (segment_displacement.cpp); std_dev / √n
//   when nothing was removed and each match is its own cluster.
// - The wall frame: a least-squares plane through reference points (the zone's, passed in,
//   or the kept matches' reference points): centroid and normal (eigenvector of the
//   smallest eigenvalue of their covariance), the normal oriented like M3C2's (n · v ≥ 0;
//   with the scanner's position, positive = towards the scanner). In the plane:
//   horizontal h = (up × n)/|up × n| (to the right seen from the front) and vertical
//   v = n × h (up the wall). A surface within 1° of horizontal has no horizontal direction
//   in its plane: h is then the project x axis projected into the plane (`horizontal_surface`).
//   Fewer than 3 points, or points (nearly) on one line, leave the frame undefined.
// - The wall components: each kept vector projected on n, h and v; their mean, sample
//   standard deviation and standard error (this keeps the correlation of the components).
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/keypoints/keypoint_match.hpp"
#include "algorithms/keypoints/outlier_filters.hpp"
#include "algorithms/keypoints/parameters.hpp"
#include "algorithms/m3c2/parameters.hpp"

namespace tlsmon::keypoints {

namespace segment_detail {
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

// A plane fitted to a wall's reference points and the directions measured in it.
struct WallFrame {
    Eigen::Vector3d centroid = Eigen::Vector3d::Constant(segment_detail::kNaN);
    Eigen::Vector3d normal = Eigen::Vector3d::Constant(segment_detail::kNaN);
    Eigen::Vector3d horizontal = Eigen::Vector3d::Constant(segment_detail::kNaN);  // in the plane
    Eigen::Vector3d vertical = Eigen::Vector3d::Constant(segment_detail::kNaN);    // in the plane
    double rms = segment_detail::kNaN;  // m, RMS distance of the points from the plane
    std::size_t points = 0;
    bool horizontal_surface = false;  // normal within 1° of up: h is the projected x axis
    std::string undefined_reason;     // empty when defined
    bool defined() const { return normal.allFinite(); }
    // The directions as rows: (normal, h, v) of a project-frame vector.
    Eigen::Matrix3d rows() const {
        Eigen::Matrix3d m;
        m.row(0) = normal.transpose(), m.row(1) = horizontal.transpose(),
        m.row(2) = vertical.transpose();
        return m;
    }
};

// The plane through `points` and its in-plane directions; `up` is the project frame's up.
WallFrame fit_wall_frame(std::span<const Eigen::Vector3d> points,
                         const m3c2::Orientation& orientation,
                         const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

struct SegmentParameters {
    std::size_t min_matches =
        static_cast<std::size_t>(Parameters{}.min_matches);  // fewer: undefined
    m3c2::Orientation orientation;                           // of the wall's normal
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();           // project frame's up
    // Matches whose reference anchors share a cell of this many pixels err together (their
    // refinement patches overlap): one cluster of the standard error. 0: each its own.
    double cluster_px = 0;
};

struct SegmentDisplacement {
    int segment = -1;
    std::size_t matches = 0;  // in the segment
    std::size_t count = 0;    // kept by the outlier filters
    Eigen::Vector3d mean = Eigen::Vector3d::Constant(segment_detail::kNaN);     // m
    Eigen::Vector3d std_dev = Eigen::Vector3d::Constant(segment_detail::kNaN);  // m, per component
    Eigen::Vector3d standard_error =
        Eigen::Vector3d::Constant(segment_detail::kNaN);  // m, the trimmed mean's (above)
    WallFrame wall;
    // Along (normal, surface horizontal, surface vertical), m.
    Eigen::Vector3d along = Eigen::Vector3d::Constant(segment_detail::kNaN);
    Eigen::Vector3d along_std_dev = Eigen::Vector3d::Constant(segment_detail::kNaN);
    Eigen::Vector3d along_standard_error = Eigen::Vector3d::Constant(segment_detail::kNaN);
    std::string undefined_reason;  // empty when defined
    // The share of the zone's wall area the figures stand for, when stratified by bands
    // (zone_strata.hpp); NaN: the plain mean of the kept matches.
    double covered_area_share = segment_detail::kNaN;

    bool defined() const { return undefined_reason.empty(); }
    double along_normal() const { return along[0]; }
    double along_surface_horizontal() const { return along[1]; }
    double along_surface_vertical() const { return along[2]; }
};

// A match's cluster for the standard errors: the cell of cluster_px × cluster_px pixels its
// reference anchor lies in, per scan (matches whose refinement patches overlap err
// together); its own `index` when cluster_px is 0.
std::uint64_t match_cluster(const KeypointMatch& m, std::size_t index, double cluster_px);

// One segment's figures from the matches with KeypointMatch::segment == `segment` that the
// filters kept (removed_by[i] == none; removed_by has one entry per match). `wall`: the
// zone's plane when known; otherwise it is fitted to the kept matches' reference points.
SegmentDisplacement segment_displacement(std::span<const KeypointMatch> matches,
                                         std::span<const OutlierFilter> removed_by, int segment,
                                         const SegmentParameters& parameters,
                                         const std::optional<WallFrame>& wall = std::nullopt);

// The vertical-angle band of a vertical angle (elevation, rad, 0 at the horizon): band k
// holds [−90° + k·width, −90° + (k+1)·width); +90° falls in the last band. Throws on a
// width outside (0, 180°] or a non-finite or out-of-range angle.
int vertical_angle_band(double elevation, double width);
// The band's bounds [lower, upper) in rad.
std::pair<double, double> vertical_angle_band_bounds(int band, double width);
// Each match's band by its reference vertical angle (default width 5°, the case study's).
std::vector<int> vertical_angle_bands(std::span<const KeypointMatch> matches,
                                      double width = std::numbers::pi / 36);

}  // namespace tlsmon::keypoints
