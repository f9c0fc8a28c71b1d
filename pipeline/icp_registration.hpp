#pragma once
// ICP on the configured stable regions (ground around the pier's foot, foundation blocks,
// abutments; never the monitored structure), as refinement of an accepted target
// registration and as the fallback when the targets are too few (`registration.icp`,
// docs/registration.md, "ICP on stable regions").
//
// Only points inside a [[stable_region]] box take part: the reference's, cropped, thinned to
// voxel centroids and given normals once (a reference-cache product), and the epoch's,
// cropped after the starting transformation and thinned alike. PCL's point-to-plane ICP
// (pipeline/pcl_adapter.hpp) finds the pairs; the adjustment and its cluster-robust covariance
// are algorithms/registration/point_to_plane.hpp's.
//   refine:   from the targets' transformation; combined with it by weights when the two
//             agree (χ² of their difference), else the targets' is kept;
//   fallback: when the targets are refused as too few (or degenerate), from the identity
//             (the drift is millimetres to centimetres); the ICP's transformation is the
//             epoch's when it passes its own gate.
// The method is recorded: "targets", "targets+icp" or "icp" (+ "+atmosphere").
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/pcl_adapter.hpp"
#include "pipeline/registration_stage.hpp"

namespace tlsmon {

// The reference's stable surface: thinned points inside the regions with their normals.
struct StableSurface {
    SurfaceSample sample;
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // the reference's scanner
    std::size_t cropped = 0;                              // points inside before thinning

    std::string encode() const;
    static StableSurface decode(std::string_view payload);
};

StableSurface build_stable_surface(const IcpConfig& config, const std::vector<Scan>& scans);

// The epoch's points inside the regions once `start` (epoch -> reference) is applied, each
// range first scaled by 1/range_scale about its scanner (1: no correction); epoch frame.
std::vector<Eigen::Vector3d> points_in_stable_regions(const IcpConfig& config,
                                                      const std::vector<Scan>& scans,
                                                      const Eigen::Matrix4d& start,
                                                      double range_scale = 1.0);

// ICP alone from `start`: the measurement, with `transform` set when the adjustment could be
// made; `refused` says why it cannot be used on its own gate (pairs, overlap, RMS,
// convergence). The reference surface is scaled by 1/reference_scale about its scanner.
IcpMeasurement measure_icp(const RegistrationConfig& config, const StableSurface& surface,
                           const std::vector<Scan>& scans, const Eigen::Matrix4d& start,
                           const RangeScales& scales = {});

// Refinement and fallback on a result of register_epoch, as `config.icp.mode` asks.
void apply_icp(const RegistrationConfig& config, const StableSurface& surface,
               const std::vector<Scan>& scans, const RangeScales& scales,
               RegistrationResult& result);

// The stage's hook: the surface from the reference cache, then apply_icp. Nothing when the
// mode is off or no region is configured.
void apply_icp(const RegistrationConfig& config, const EpochInput& input, ReferenceEpoch& reference,
               ReferenceCache& cache, const RangeScales& scales, RegistrationResult& result);

// "targets", "planes", "targets+planes", "stable_areas" (or "+stable_areas" when joint) or "icp",
// with "+icp" for a refinement and
// "+atmosphere" when the ranges were corrected.
std::string registration_method(const RegistrationResult& result);

// The ICP's figures, the `icp` member of the registration row's quality_json (a NaN is null).
nlohmann::json icp_quality(const IcpMeasurement& icp);

}  // namespace tlsmon
