#pragma once
// What one processed epoch produces: registration, target observations, zone results (the
// points of the time series), core point arrays, and the alarm and system events it caused.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/alarm_store.hpp"
#include "storage/epochs.hpp"
#include "storage/event_log.hpp"
#include "storage/keypoint_models.hpp"
#include "storage/meteo_sidecar.hpp"
#include "storage/thermal_store.hpp"

namespace tlsmon {

// Registration of one epoch onto the reference targets (filled by the registration stage).
// The method and status of an epoch that nothing registered (pipeline: no targets, no ICP).
inline constexpr const char* kUnregistered = "unregistered";

struct RegistrationRow {
    std::string method;                  // e.g. "targets-helmert"
    std::array<double, 16> transform{};  // 4x4 row-major, scan frame -> project frame
    std::int64_t target_count = 0;       // targets used
    double rms_m = 0;                    // RMS of the target residuals
    double max_residual_m = 0;
    std::optional<double> sigma0;     // a-posteriori standard deviation of unit weight
    bool accepted = false;            // passed the quality gate
    std::string quality_json = "{}";  // further quality figures, free form
    // The test's verdict (algorithms/registration/target_tests.hpp) and why, when not accepted.
    std::string status;
    std::string reason;
    // ω, φ, κ (rad), tx, ty, tz (m) and their σ; the quaternion (w, x, y, z): absent when no
    // transformation was estimated.
    std::optional<std::array<double, 6>> parameters;
    std::optional<std::array<double, 6>> sigmas;
    std::optional<std::array<double, 4>> quaternion;
    std::optional<double> variance_factor;
    std::optional<std::int64_t> redundancy;
};

// The registration's σ at a zone (largest 3-D σ over its box).
struct RegistrationZoneSigma {
    std::string zone;
    double max_sigma_3d_m = 0;
};

struct TargetObservation {
    std::string target;                          // name of the reference target
    std::string kind;                            // "sphere", "plane", ...
    std::array<double, 3> measured{};            // centre in the scan frame, metres
    std::array<double, 3> residual{};            // project frame, metres
    bool stable = true;                          // passed the stability test
    bool used = true;                            // used in the transformation estimate
    std::string status;                          // found, not_found, bad_fit, excluded
    std::string reason;                          // why, when not found
    std::string use;                             // used, not_usable, excluded_outlier, suspect
    std::optional<std::array<double, 3>> sigma;  // of the measured centre, m
    std::optional<double> statistic;             // outlier test
    std::optional<double> critical;
    std::optional<double> minimal_detectable_bias_m;
};

// A reference plane matched in the epoch by the registration on planes: its change under the
// accepted transformation (schema 0009_plane_observations.sql).
struct PlaneRow {
    std::int64_t plane = 0;                      // the reference plane's index
    std::string zone;                            // "" outside every zone
    std::string role;                            // datum, moved, monitored
    std::array<double, 3> normal{}, centroid{};  // the reference plane, reference frame
    std::int64_t reference_points = 0, epoch_points = 0;
    std::array<double, 3> change{};  // tilt towards u, towards v (rad), shift along n (m)
    std::array<double, 3> sigma{};   // of each
    double statistic = 0, critical = 0;
    bool significant = false;
};

// A supervoxel of the reference, as the registration on stable areas segmented it
// (schema 0010_stable_areas.sql).
struct SupervoxelRow {
    std::array<double, 3> centroid{}, normal{};  // reference frame
    std::int64_t voxels = 0;
    double roughness_m = 0;  // RMS distance of its voxels from its plane
};

// One epoch's stable-area mask: per supervoxel of its reference's segmentation, its state
// (0 stable, 1 unstable, 2 unknown, 3 not planar), change along its normal and LoD (m; NaN:
// none). `supervoxels` is written once per reference and segmentation.
struct StableAreaMask {
    std::int64_t reference_epoch = 0;
    std::string segmentation;  // the supervoxels' parameters
    std::vector<SupervoxelRow> supervoxels;
    std::vector<std::uint8_t> states;
    std::vector<float> changes, lods;
    std::int64_t stable = 0, unstable = 0;
    double stable_share = 0;
};

// Aggregate of one quantity over one zone in one epoch: one point of a time series.
struct ZoneResult {
    std::string zone;      // zone name (the zone must exist: Site::upsert_zone)
    std::string quantity;  // e.g. "m3c2_mean_m", "keypoint_dz_m"
    double value = 0;
    std::optional<double> uncertainty;  // e.g. LoD95 or standard error, same unit as value
    std::int64_t n = 0;                 // number of core points / keypoints aggregated
    bool significant = false;           // |value| > LoD
};

// One value per core point (in the reference's core point order), stored as float32.
struct CorePointArray {
    std::string quantity;  // e.g. "m3c2_distance_m", "lod95_m"
    std::vector<float> values;
};

// Everything one processed epoch produces, written by ResultsWriter::commit in one
// transaction.
// One pipeline stage that ran for the epoch, in the order they ran.
struct StageRun {
    std::string stage;
    double ms = 0;
    std::string rejected;  // why this stage rejected the epoch; "" when it ran through
    std::string note;      // what it measured, in a few words
};

// A zone a stage's rows name that the configuration does not list (keypoint bands):
// created, or its definition updated, in the epoch's commit.
struct NewZone {
    std::string name;
    std::string definition_json;
};

struct EpochResults {
    // done (analysed) or rejected (quality gate; reason required, zone results not allowed).
    EpochStatus outcome = EpochStatus::done;
    std::string reason;
    std::optional<std::int64_t> point_count;
    EpochTimings timings;
    std::vector<StageRun> stages;
    std::optional<std::string> archive_path;
    std::optional<RegistrationRow> registration;
    std::vector<TargetObservation> targets;
    std::vector<std::string> target_exclusions;  // targets this epoch excluded as moved
    std::vector<RegistrationZoneSigma> registration_zone_sigmas;
    std::vector<PlaneRow> planes;                // the registration on planes' matched planes
    std::optional<StableAreaMask> stable_areas;  // the registration on stable areas' mask
    std::vector<NewZone> new_zones;              // before zone_results, which may name them
    std::vector<ZoneResult> zone_results;
    std::vector<CorePointArray> core_point_arrays;
    std::vector<KeypointModelRow> keypoint_models;  // d(t, z) refitted with this epoch
    std::vector<ThermalModelRow> thermal_models;    // fitted in this epoch's commit
    std::vector<ThermalCompensationRow> thermal_compensations;
    std::vector<AlarmState> alarm_states;  // new states of the rules this epoch changed
    std::vector<AlarmEvent> alarm_events;
    std::vector<SystemEvent> system_events;
    // The meteo sidecar the epoch was processed with (used or rejected), if it had one.
    std::optional<MeteoSidecar> meteo;
};

}  // namespace tlsmon
