#pragma once
// Targetless registration on the stable areas the scene shows by itself
// (`registration.method` with `stable_areas`; docs/registration.md, "Registration on stable
// areas"), after the supervoxel-based registration of the thesis on rigid patches in TLS
// point clouds (its chapter 4):
//   1. the reference is thinned to voxel centroids and over-segmented into supervoxels
//      (VCCS, pipeline/pcl_adapter.hpp), each a patch of plane with its centroid, normal,
//      surface variation and voxel count (algorithms/registration/supervoxel_change.hpp);
//      once, a reference-cache product;
//   2. the epoch, thinned alike, is put on the coarse transformation (the targets' or the
//      planes' when accepted, else the last accepted registration's pose for a fixed
//      station, else the identity) and each voxel assigned to the supervoxel of its nearest
//      reference voxel;
//   3. rounds: point-to-plane adjustment on the current stable set (each voxel against its
//      supervoxel's plane; cluster-robust covariance with each supervoxel a cluster) →
//      every supervoxel's change along its normal with its LoD → the significant ones leave
//      the set (and may return) → until the set no longer changes or stable_max_iterations;
//   4. guards: stable supervoxels and share at least, the normal matrix's condition at
//      most; below them the epoch is refused with the reason, never analysed on a weak
//      datum.
// Configured [[stable_region]] tables are hints: the first round uses only the supervoxels
// inside them (when they hold all six parameters); every later round tests every supervoxel.
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/registration/supervoxel_change.hpp"
#include "pipeline/registration_on_planes.hpp"
#include "pipeline/registration_stage.hpp"

namespace tlsmon {

// The reference's supervoxels: its voxels with the supervoxel each belongs to, and the
// supervoxels as patches of plane.
struct ReferenceSupervoxels {
    std::vector<Eigen::Vector3d> samples;  // voxel centroids, ranges as measured
    std::vector<std::int32_t> label;       // per sample: its supervoxel, −1 none
    std::vector<registration::SupervoxelPatch> patches;
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // the reference's scanner
    double milliseconds = 0;                              // to build

    std::string encode() const;
    static ReferenceSupervoxels decode(std::string_view payload);
};

ReferenceSupervoxels build_supervoxels(const StableAreaConfig& config,
                                       const std::vector<Scan>& scans);

// The canonical text of the segmentation's parameters (the supervoxels' cache key).
std::string supervoxel_parameters(const StableAreaConfig& config);

// The reference's supervoxels from the reference cache (built once): the registration on
// stable areas and patch-based M3C2 share them.
std::shared_ptr<const ReferenceSupervoxels> cached_supervoxels(const StableAreaConfig& config,
                                                               ReferenceEpoch& reference,
                                                               ReferenceCache& cache);

// Whether a supervoxel may enter the datum at all: a patch of plane with enough voxels, not a
// sheet of rays from `viewpoint` (mixed returns along the beams at an edge).
bool is_planar(const StableAreaConfig& config, const registration::SupervoxelPatch& patch,
               const Eigen::Vector3d& viewpoint);

// The iteration from `start` (epoch -> reference): the measurement, with `transform` set and
// `refused` empty when it holds. `hints`: the [[stable_region]] tables.
StableAreaMeasurement measure_stable_areas(const RegistrationConfig& config,
                                           const ReferenceSupervoxels& reference,
                                           const std::vector<Scan>& scans,
                                           const Eigen::Matrix4d& start,
                                           const RangeScales& scales = {});

// Every supervoxel's change under T alone (no adjustment): for comparisons with a known
// transformation.
StableAreaMeasurement supervoxel_changes(const RegistrationConfig& config,
                                         const ReferenceSupervoxels& reference,
                                         const std::vector<Scan>& scans,
                                         const registration::RigidTransform& T,
                                         const RangeScales& scales = {});

// A coarse pose found without a prior, and the station change it means against the start it
// is given (coarse_pose_from_planes); nothing when none was found.
using CoarsePoseSearch =
    std::function<std::optional<CoarsePose>(const registration::RigidTransform& start)>;

// On a result of register_epoch (and apply_planes): joint with an accepted transformation
// (started from it, combined when the two agree), alone otherwise (from `prior`, else the
// identity; when refused from there, once more from `coarse`'s pose if it finds one).
void apply_stable_areas(const RegistrationConfig& config, const ReferenceSupervoxels& reference,
                        const std::vector<Scan>& scans, const RangeScales& scales,
                        RegistrationResult& result,
                        const std::optional<registration::RigidTransform>& prior = std::nullopt,
                        const CoarsePoseSearch& coarse = {});

// The stage's hook: the supervoxels from the reference cache, then apply_stable_areas (from
// the history's last accepted pose), then the unstable areas new in this epoch (from the
// history's masks). Nothing without `stable_areas` in the method, or for the reference epoch.
void apply_stable_areas(const RegistrationConfig& config, const EpochInput& input,
                        ReferenceEpoch& reference, ReferenceCache& cache, const RangeScales& scales,
                        RegistrationResult& result, const StageHistory& history);

// The supervoxels outside the zones unstable in `m` and in the `persistent_epochs` − 1 masks
// before it (`before`: state bytes, newest first), and not in the one before those, grouped
// into areas of neighbours; areas of fewer than three supervoxels are left out.
std::vector<registration::UnstableArea> new_unstable_areas(
    const RegistrationConfig& config, const StableAreaMeasurement& m,
    const std::vector<std::vector<std::uint8_t>>& before);

// The figures, the `stable_areas` member of the registration row's quality_json.
nlohmann::json stable_area_quality(const StableAreaMeasurement& m);

}  // namespace tlsmon
