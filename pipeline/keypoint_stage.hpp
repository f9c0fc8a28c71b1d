#pragma once
// Stage "keypoints": the keypoint displacement method (Hochmoselbrücke case study;
// docs/keypoints.md) of each epoch against the reference epoch, per segment into the time
// series, and the displacement model d(t, z) refitted over every epoch so far.
//
// Reference product (the reference cache, stage "keypoints"; keypoint_reference.hpp): per
// structured scan, the keypoints and descriptors (detected inside the zones, or everywhere
// for bands) taken to 3-D; per zone the wall frame. Reused from memory, or from the
// database after a restart; the reference's images are not kept (nothing after detection
// needs them).
//
// Each epoch, per structured scan (paired with the reference's by their order in the file):
// its spherical images, keypoints and descriptors (OpenCV, through
// algorithms/keypoints/opencv_features.hpp), matching in the angular window, 3-D through
// the epoch's range image, then into the reference frame by the same map as M3C2 (range
// scale about the scanner, the registration; m3c2_stage.hpp, epoch_to_reference). Per
// segment, the matches of the scan that samples it finest (a detail scan over an
// overview), then the outlier filters, the mean vector and its components along the wall,
// as zone rows (keypoint_results.hpp) with LoD95 = 1.96 · √(standard error² + registration
// σ²), the registration's σ at the segment's centroid along each figure's direction.
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
#include "pipeline/keypoint_reference.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/stage.hpp"
#include "storage/epoch_results.hpp"

namespace tlsmon {

// The canonical text of every parameter the reference product depends on (its cache key).
std::string keypoint_reference_parameters(const KeypointConfig& config);

KeypointReference prepare_keypoint_reference(const KeypointConfig& config,
                                             const std::vector<Scan>& scans);

// One epoch's matches in the reference frame, with each step's wall time.
struct KeypointEpoch : keypoints::DroppedCounts {
    std::vector<keypoints::KeypointMatch> matches;  // segment −1, every scan
    std::size_t scans = 0;                          // structured scans paired with the reference's
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
    // The registration's covariance at the segment's centroid (m², project frame);
    // keypoints.registration_error² · I without a registration.
    Eigen::Matrix3d registration_covariance = Eigen::Matrix3d::Zero();
    // The matches the segment was computed from, each with the filter that removed it
    // (OutlierFilter::none: kept).
    std::vector<keypoints::KeypointMatch> matches;
    std::vector<keypoints::OutlierFilter> removed_by;
};

struct KeypointSegmentsResult {
    std::vector<KeypointSegmentResult> segments;
    double filtering_s = 0;
};

// Step 5 and 6 per segment (zones: each zone's matches by their reference point, a match in
// two overlapping zones counts in both; bands: by the reference's vertical angle), on the
// matches of the scan with the smallest median range × step in the segment.
KeypointSegmentsResult keypoint_segments(const KeypointConfig& config,
                                         const KeypointReference& reference,
                                         std::vector<keypoints::KeypointMatch> matches,
                                         const StageOutputs& outputs);

// The zone names the model gathers its stored observations from: the zones, or every band.
std::vector<std::string> keypoint_segment_zones(const KeypointConfig& config);

// The stage: zone rows per segment, one model row per config.model_quantities (over the
// stored series, the history's, and this epoch), and the band zones the rows name
// (EpochResults::new_zones). Runs when enabled with zones or bands (site_stages); an epoch
// without a structured scan is not measured by it.
class KeypointStage final : public ReferenceStage<KeypointReference> {
  public:
    explicit KeypointStage(KeypointConfig config) : config_(std::move(config)) {}
    const char* name() const override { return "keypoints"; }
    std::string reference_parameters() const override;
    KeypointReference prepare_reference(const std::vector<Scan>& reference_scans) const override;
    StageVerdict measure(StageContext& ctx, const KeypointReference& reference) const override;
    std::string not_measured(const StageContext& ctx) const override;

  private:
    KeypointConfig config_;
};

}  // namespace tlsmon
