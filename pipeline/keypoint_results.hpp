#pragma once
// What the keypoint stage stores (docs/keypoints.md, "In the database"): a segment's
// displacement as zone rows of the time series, vertical-angle bands as zones, and the
// displacement model d(t, z) as a model row, with its observations gathered from the series.
// Plain functions from the kernels' results to storage rows; the stage that runs the images,
// matching and 3-D (OpenCV) calls them.
#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "algorithms/keypoints/displacement_model.hpp"
#include "algorithms/keypoints/segment_displacement.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// The zone quantities of the keypoint method.
inline constexpr const char* kKeypointDx = "keypoint_dx_m";
inline constexpr const char* kKeypointDy = "keypoint_dy_m";
inline constexpr const char* kKeypointDz = "keypoint_dz_m";
inline constexpr const char* kKeypointAlongNormal = "keypoint_along_normal_m";
inline constexpr const char* kKeypointAlongSurfaceH = "keypoint_along_surface_h_m";
inline constexpr const char* kKeypointAlongSurfaceV = "keypoint_along_surface_v_m";
inline constexpr const char* kKeypointCount = "keypoint_count";
inline constexpr const char* kKeypointHeight = "keypoint_height_m";
// Every zone quantity the stage writes (the alarm rules name them).
inline constexpr std::array<const char*, 8> kKeypointQuantities = {kKeypointDx,
                                                                   kKeypointDy,
                                                                   kKeypointDz,
                                                                   kKeypointAlongNormal,
                                                                   kKeypointAlongSurfaceH,
                                                                   kKeypointAlongSurfaceV,
                                                                   kKeypointCount,
                                                                   kKeypointHeight};

// A segment's rows (zone `zone`):
// - keypoint_count: value = the matches the filters kept, n = the segment's matches; always.
// - when the segment is defined (docs/keypoints.md, step 6), with n = kept matches:
//   keypoint_dx_m, keypoint_dy_m, keypoint_dz_m (project frame) and, when its wall frame is
//   defined, keypoint_along_normal_m, keypoint_along_surface_h_m, keypoint_along_surface_v_m
//   and keypoint_height_m (the wall centroid's z, the model's z). Uncertainty: LoD95 =
//   1.96 · √(SE² + uᵀ·C·u), SE the segment's standard error of the figure, u the figure's
//   direction (x, y, z, or the wall's normal, horizontal, vertical) and C
//   `registration_covariance` (m², project frame: the registration's at the segment) — Lague
//   2013, eq. 1, with the standard error of the segment's mean in place of the cylinders'
//   term and the registration's σ along the figure (the matches' noise and the datum are
//   independent); significant when |value| > LoD95. Over 70 independent series of the demo
//   scene 97.1 % of the along-surface errors (h and v) lie within it (docs/calibration.md,
//   "The methods over independent series"); the linear sum with the registration's worst
//   direction, used before, covered 98.8 % and 100 % over 40 others.
// Never a NaN row: an undefined figure is left out.
std::vector<ZoneResult> keypoint_zone_results(
    const std::string& zone, const keypoints::SegmentDisplacement& segment,
    const Eigen::Matrix3d& registration_covariance = Eigen::Matrix3d::Zero());

// Vertical-angle band k of `width` (rad) as a zone: "keypoint_band_<lo>_<hi>" in degrees
// (e.g. keypoint_band_-5_0, keypoint_band_10_15) and its definition JSON
// {"vertical_angle_deg":[lo,hi]}.
std::string keypoint_band_zone(int band, double width);
std::string keypoint_band_zone_definition(int band, double width);

// One observation of the model with the zone it came from.
struct KeypointModelInput {
    std::string zone;
    EpochId epoch = 0;
    keypoints::ModelObservation observation;
};

// The model's observations of the stored epochs: for each zone, every epoch with both
// `quantity` and keypoint_height_m, t = hours since `reference_acquired`.
std::vector<KeypointModelInput> stored_model_inputs(const SeriesReader& series,
                                                    std::span<const std::string> zones,
                                                    const std::string& quantity,
                                                    UtcSeconds reference_acquired);

// The model row of a fit over `inputs` (in the fit's order), with the residuals of the
// inputs of epoch `fitting_epoch`.
KeypointModelRow keypoint_model_row(const std::string& quantity, const std::string& variable,
                                    const keypoints::DisplacementModel& model,
                                    std::span<const KeypointModelInput> inputs,
                                    EpochId fitting_epoch);

}  // namespace tlsmon
