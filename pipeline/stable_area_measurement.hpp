#pragma once
// What the registration on stable areas measured in one epoch
// (pipeline/stable_area_registration.hpp), as the registration row and the stable-area mask
// record it.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/registration/point_to_plane.hpp"
#include "algorithms/registration/rigid_transform.hpp"
#include "algorithms/registration/supervoxel_change.hpp"
#include "algorithms/registration/unstable_areas.hpp"
#include "pipeline/plane_measurement.hpp"

namespace tlsmon {

// Each reference supervoxel in one epoch. Stored as one byte per supervoxel.
enum class SupervoxelState : std::uint8_t {
    stable = 0,      // its change not significant: in the datum, unless inside a [[zone]]
    unstable = 1,    // its change significant (out of the datum once so for the family)
    unknown = 2,     // too few voxels of the epoch on it (occluded, out of view)
    not_planar = 3,  // no patch of plane (leaves, edges, corners, too small): never in the datum
};
const char* name_of(SupervoxelState state);

struct StableAreaMeasurement {
    std::string role;     // "alone": the epoch's datum; "joint": combined with the targets'/planes'
    bool used = false;    // entered the epoch's transformation
    std::string refused;  // why it did not ("" when used)
    std::string start;    // where the iteration started, in words
    std::size_t supervoxels = 0;  // of the reference
    // The counts outside the zones; `monitored`: the planar ones inside (tested, never in the
    // datum; their states say what they showed).
    std::size_t stable = 0, unstable = 0, unknown = 0, not_planar = 0, monitored = 0;
    double stable_share = 0;  // the stable supervoxels' share of the voxels with a change
    int iterations = 0;
    bool settled = false;           // the stable set no longer changed
    std::size_t epoch_samples = 0;  // the epoch's voxels
    std::size_t pairs = 0, outliers = 0, clusters = 0;
    double rms = 0;  // m, of the point-to-plane distances
    // λ_min/λ_max of the normal matrix, rotations at the set's RMS radius (1: all held alike).
    double conditioning = 0;
    // Largest σ ratio of the reported covariance to the independent voxels' s0²·N⁻¹: the larger
    // of the cluster-robust one and the supervoxels' (each one observation with its own σ and
    // an error common to its cell, of σ `cell_sigma` estimated from this epoch's cells).
    double inflation = 1;
    double cell_sigma = 0;            // m
    double variance_factor = 0;       // s0², m²
    std::optional<double> agreement;  // joint: χ² of the difference (6 degrees of freedom)
    double milliseconds = 0;
    std::string targets_status;  // the verdict the stable areas replaced, when alone
    std::optional<registration::RigidTransform> transform;  // its own estimate
    // The candidates its covariance is the larger of: the last round's adjustment (s0²·N⁻¹ and
    // the cluster-robust sandwich) and the supervoxels' as observations with their cells' τ.
    std::optional<registration::PointToPlaneFit> fit;
    std::optional<registration::Covariance6> supervoxel_covariance;
    // The reference's supervoxels and what identifies them (its epoch, the segmentation's
    // parameters), for the stored mask.
    std::int64_t reference_epoch = 0;
    std::string segmentation;
    std::vector<registration::SupervoxelPatch> patches;
    // Per reference supervoxel (its index): state, change and LoD (m; NaN without a change).
    std::vector<SupervoxelState> states;
    std::vector<float> changes, lods;
    // Refused from the last pose, accepted from the planes matched without a prior, which put
    // the scanner beyond the planes' matching tolerances from it (a knocked or re-set station).
    std::optional<StationChange> station_change;
    int persistent_epochs = 0;  // registration.stable_persistent_epochs
    // Supervoxels outside the zones that have just been unstable for `stable_persistent_epochs`
    // epochs in a row, neighbours (centroids within two seeds) grouped: a creeping slope, a
    // settling fill, a parked vehicle. Reported once, when they get there.
    std::vector<registration::UnstableArea> new_unstable_areas;
};

}  // namespace tlsmon
