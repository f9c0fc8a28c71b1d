#pragma once
// What the ICP on stable regions needs of the site (docs/configuration.md, [registration]
// icp_* keys and the [[stable_region]] tables; docs/registration.md, "ICP on stable regions").
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/scanner_noise.hpp"

namespace tlsmon {

// A part of the site that does not move: the ground around the pier's foot, a foundation
// block, an abutment. Never the monitored structure. An axis-aligned box, project frame.
struct StableRegion {
    std::string name;
    Eigen::Vector3d min = Eigen::Vector3d::Zero();
    Eigen::Vector3d max = Eigen::Vector3d::Zero();
    bool contains(const Eigen::Vector3d& p) const {
        return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
    }
};

// When ICP runs: never; to refine an accepted target registration; in place of the targets
// when too few are usable; or both.
enum class IcpMode { off, refine, fallback, both };

struct IcpConfig {
    IcpMode mode = IcpMode::off;
    double max_correspondence_distance = 0.05;  // m, pairs farther apart are not matched
    int max_iterations = 50;
    double voxel_size = 0.10;   // m, both clouds are thinned to one centroid per voxel
    double min_overlap = 0.3;   // share of the epoch's thinned points with a pair
    int min_points = 500;       // pairs at least
    double max_rms = 0.005;     // m, RMS of the point-to-plane distances
    double cluster_size = 1.0;  // m, cells whose residuals may be correlated (covariance)
    // The ICP's σ multiplied by this; 1: as the epoch's residuals give it, an error common to
    // each cell included (point_to_plane.hpp), which holds RMS(error/σ) near 1 on the
    // simulator without a factor (docs/registration.md).
    double sigma_factor = 1.0;
    // [station]: where the ground is so grazing that the beam's angular noise scatters a scan
    // row along its beams (icp_registration.cpp, measure_icp).
    ScannerNoise noise;
    std::vector<StableRegion> regions;  // none: ICP cannot run
    // The bounds of the no-change check zones ([[zone]] no_change): never in the regions.
    std::vector<StableRegion> excluded;
    bool refines() const { return mode == IcpMode::refine || mode == IcpMode::both; }
    bool falls_back() const { return mode == IcpMode::fallback || mode == IcpMode::both; }
};

}  // namespace tlsmon
