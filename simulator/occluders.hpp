#pragma once
// Things between the scanner and the pier that are not part of the monitored scene:
// - occluders: a vehicle (a box along its path) or a person (a vertical cylinder) that is
//   present at an epoch with its probability and then stands at a uniformly random place on
//   its path (seeded per epoch and occluder, the same for any thread count);
// - vegetation: a bush, an ellipsoid on the ground filled with leaves. The ellipsoid's
//   bounding box is cut into voxels of `leaf_spacing`; a voxel whose centre lies inside the
//   ellipsoid and above the ground holds a leaf (a small sphere) with probability `density`,
//   at a fixed random offset plus a per-epoch sway of up to `sway` (wind), always inside its
//   voxel. A ray walks the voxels front to back (Amanatides & Woo 1987), so the first leaf it
//   meets is the nearest; every sub-ray of a footprint sees the same leaves, and the points
//   on the bush differ from epoch to epoch while the ground under it does not.
#include <Eigen/Core>
#include <vector>

#include "simulator/geometry.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct OccluderState {
    bool present = false;
    Eigen::Vector3d base = Eigen::Vector3d::Zero();  // centre of its footprint, on the ground
    double heading = 0.0;                            // rad from project +x (vehicles)
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  // bounds
};

// Where each occluder is at `epoch` (one per Site::occlusion.occluders).
std::vector<OccluderState> occluder_states(const Site& site, int epoch);

struct VegetationState {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();                            // ellipsoid centre
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  // voxel grid
    Eigen::Vector3i cells = Eigen::Vector3i::Zero();
    double ground_z = 0.0;  // ground height at the centre
    std::uint64_t seed = 0, epoch_seed = 0;
};

std::vector<VegetationState> vegetation_states(const Site& site, int epoch);

struct SolidHit {
    double t = kNoHit;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

SolidHit intersect_occluder(const Occluder& o, const OccluderState& s,
                            const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double t_max);

SolidHit intersect_vegetation(const Vegetation& v, const VegetationState& s,
                              const Eigen::Vector3d& origin, const Eigen::Vector3d& d,
                              double t_max);

// Throws tlsmon::Error naming the patch when leaf_radius + sway exceeds half the spacing.
void validate_occlusion(const Occlusion& occlusion);

const char* occluder_kind_name(Occluder::Kind k);

}  // namespace tlsmon::sim
