#pragma once
// Stage "keypoints": the keypoint displacement method (Hochmoselbrücke case study;
// docs/keypoints.md) of each epoch against the reference epoch, per segment into the time
// series, and the displacement model d(t, z) refitted over every epoch so far.
//
// Reference product (the reference cache, stage "keypoints"): the reference scan's
// keypoints and descriptors (detected inside the zones, or everywhere for bands), each
// with its lattice angles, its polar coordinates and its point in the project frame (only
// keypoints the range image can take to 3-D are kept), the scanner's position, and per zone
// the wall frame fitted to the reference's points in it. Reused from memory, or from the
// database after a restart; the reference's images are not kept (nothing after detection
// needs them).
//
// Each epoch: its spherical images, keypoints and descriptors (OpenCV, through
// algorithms/keypoints/opencv_features.hpp), matching in the angular window, 3-D through
// the epoch's range image, then into the reference frame by the same map as M3C2 (range
// scale about the scanner, the registration; m3c2_stage.hpp, epoch_to_reference). Per
// segment: the outlier filters, the mean vector and its components along the wall, as zone
// rows (keypoint_results.hpp) with LoD95 = 1.96 · (standard error + registration σ), the
// registration's σ at the segment's centroid in its worst direction.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/keypoints/features.hpp"
#include "algorithms/keypoints/keypoint_match.hpp"
#include "algorithms/keypoints/keypoint_matching.hpp"
#include "algorithms/keypoints/keypoint_to_3d.hpp"
#include "algorithms/keypoints/outlier_filters.hpp"
#include "algorithms/keypoints/segment_displacement.hpp"
#include "algorithms/keypoints/spherical_image.hpp"
#include "pipeline/keypoint_config.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/stage.hpp"
#include "storage/epoch_results.hpp"

namespace tlsmon {

// What the keypoint stage keeps of the reference epoch.
struct KeypointReference {
    static constexpr int kFormatVersion = 2;
    static constexpr const char* kStage = "keypoints";

    keypoints::Features features;  // kept keypoints, their descriptors row by row
    std::vector<keypoints::AngularPosition> positions;  // lattice angles, per keypoint
    // Where each keypoint is measured: its own sub-pixel position, or with `refine` the
    // pixel nearest it (an exact return) whose intensity patch is sought in the epoch.
    std::vector<double> anchor_rows, anchor_columns;
    std::vector<keypoints::Polar> polar;  // scanner frame, at the anchor
    std::vector<Eigen::Vector3d> points;  // project frame, at the anchor
    int patch_radius = 0;                 // 0: no patches (no refinement)
    std::vector<float> patches;           // (2·radius + 1)² intensities per keypoint
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();  // the reference scan's position
    double angular_step = 0;   // rad, the larger of the images' horizontal and vertical steps
    std::size_t detected = 0;  // keypoints detected (before description and 3-D)
    std::vector<std::string> zone_names;      // zones mode, in the configuration's order
    std::vector<keypoints::WallFrame> walls;  // per zone, from the reference's points
    double seconds = 0;                       // time it took to build

    std::string encode() const;
    static KeypointReference decode(std::string_view payload);
};

// The canonical text of every parameter the reference product depends on (its cache key).
std::string keypoint_reference_parameters(const KeypointConfig& config);

KeypointReference prepare_keypoint_reference(const KeypointConfig& config,
                                             const std::vector<Scan>& scans);

// One epoch's matches in the reference frame, with each step's wall time.
struct KeypointEpoch : keypoints::DroppedCounts {
    std::vector<keypoints::KeypointMatch> matches;  // segment −1
    std::size_t detected = 0, described = 0, pairs = 0;
    std::size_t dropped_patch = 0;  // the refinement did not find the patch
    double images_s = 0, detection_s = 0, description_s = 0, matching_s = 0, to_3d_s = 0;
};

KeypointEpoch measure_keypoints(const KeypointConfig& config, const KeypointReference& reference,
                                const std::vector<Scan>& scans, const StageOutputs& outputs);

// One segment's figures and its zone (a configured zone, or keypoint_band_<lo>_<hi>).
struct KeypointSegmentResult {
    std::string zone;
    std::string band_definition;  // bands: the zone's definition JSON; zones: ""
    keypoints::SegmentDisplacement displacement;
    double registration_sigma = 0;  // m
};

struct KeypointSegmentsResult {
    std::vector<KeypointSegmentResult> segments;
    double filtering_s = 0;
};

// Step 5 and 6 per segment (zones: each zone's matches by their reference point, a match in
// two overlapping zones counts in both; bands: by the reference's vertical angle).
KeypointSegmentsResult keypoint_segments(const KeypointConfig& config,
                                         const KeypointReference& reference,
                                         std::vector<keypoints::KeypointMatch> matches,
                                         const StageOutputs& outputs);

// The zone names the model gathers its stored observations from: the zones, or every band.
std::vector<std::string> keypoint_segment_zones(const KeypointConfig& config);

// The stage: the reference product from the cache, then the epoch, into `results` (zone rows
// and one model row per config.model_quantities). `series`: the stored epochs, for the
// model; `reference_acquired`: t = 0 of the model. `new_zones` receives the band zones
// (name, definition) the rows name, which must exist before the commit.
StageVerdict run_keypoints(const KeypointConfig& config, const EpochInput& input,
                           ReferenceEpoch& reference, ReferenceCache& cache,
                           const StageOutputs& outputs, const SeriesReader& series,
                           std::vector<std::pair<std::string, std::string>>& new_zones,
                           EpochResults& results);

}  // namespace tlsmon
