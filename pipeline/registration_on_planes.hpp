#pragma once
// Registration on the scene's own planes (`registration.method = "planes"` or
// "targets+planes"; docs/registration.md, "Registration on planes and the congruence test").
//
// The reference's planes are detected once in its grid (a reference-cache product); each
// epoch's planes are detected in every structured scan of its file, matched to the
// reference's from an approximate transformation (the identity for a fixed station, or the
// targets' registration), and adjusted; the congruence test leaves out the planes that moved.
// Planes inside a [[zone]] never enter the datum — the structure is what is measured — but
// are matched and reported with their change like every other plane.
//   alone: the planes' transformation is the epoch's, when the test found a congruent set of
//          at least `plane_min_planes` planes and it passes the σ gate;
//   joint: after an accepted target registration, the two independent estimates combined by
//          their covariances (the weighted mean of two adjustments of independent
//          observations: to first order the joint adjustment), when they agree (χ²(6)).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/registration_stage.hpp"

namespace tlsmon {

// The reference's planes, largest first, ranges as measured (corrected when used).
struct ReferencePlanes {
    std::vector<registration::FittedPlane> planes;
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // the reference's scanner

    std::string encode() const;
    static ReferencePlanes decode(std::string_view payload);
};

// The planes of every structured scan in `scans` (a scan without a grid has none).
ReferencePlanes detect_scan_planes(const PlaneConfig& config, const std::vector<Scan>& scans);

// The registration on planes on a result of register_epoch, as `config.method` asks. The
// approximate transformation is the targets' (joint), else `prior` (the last accepted
// registration's), else the identity; when it matches too few planes, the matching without a
// prior (a station change when it finds the scanner elsewhere).
void apply_planes(const RegistrationConfig& config, const ReferencePlanes& reference,
                  const std::vector<Scan>& scans, const RangeScales& scales,
                  RegistrationResult& result,
                  const std::optional<registration::RigidTransform>& prior = std::nullopt);

// The stage's hook: the reference's planes from the cache, then apply_planes. Nothing for the
// method `targets` or for the reference epoch itself (its frame is the datum).
void apply_planes(const RegistrationConfig& config, const EpochInput& input,
                  ReferenceEpoch& reference, ReferenceCache& cache, const RangeScales& scales,
                  RegistrationResult& result,
                  const std::optional<registration::RigidTransform>& prior);

// A coarse pose with no approximate transformation, for another method (the stable areas
// alone, after they were refused from the last pose): the reference's planes from the cache
// (the same product as apply_planes'), the epoch's detected, both range-corrected when the
// scales allow, matched without a prior (plane_matching_without_prior.hpp); the station change
// it means against `start`. Nothing when no hypothesis explains enough planes.
struct CoarsePose {
    registration::RigidTransform approximate;
    StationChange change;  // against `start`
};
std::optional<CoarsePose> coarse_pose_from_planes(const RegistrationConfig& config,
                                                  const EpochInput& input,
                                                  ReferenceEpoch& reference, ReferenceCache& cache,
                                                  const RangeScales& scales,
                                                  const registration::RigidTransform& start);

// One line for the registration's reason and the `station_change` event.
std::string describe(const StationChange& change);

// {shift_m, turn_deg, support}, or null: in the planes' and the stable areas' figures.
nlohmann::json station_change_json(const std::optional<StationChange>& change);

// The registration on planes' figures, the `planes` member of the registration row's
// quality_json.
nlohmann::json plane_quality(const PlaneMeasurement& m);

}  // namespace tlsmon
