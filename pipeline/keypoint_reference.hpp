#pragma once
// What the keypoint stage keeps of the reference epoch (the reference cache's product of
// stage "keypoints", pipeline/keypoint_stage.hpp), and its payload format.
//
// Per structured scan of the reference epoch, in file order (an overview and its detail
// scans, simulator/scene.hpp DetailScan): the keypoints and descriptors, each with its
// lattice angles, its anchor pixel, its polar coordinates and its point in the project
// frame (only keypoints the range image can take to 3-D are kept), the intensity patches
// the refinement seeks, and the scan's angular step. Once for the epoch: the scanner's
// position and per zone the wall frame fitted to the reference's points in it.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/keypoints/features.hpp"
#include "algorithms/keypoints/keypoint_matching.hpp"
#include "algorithms/keypoints/keypoint_to_3d.hpp"
#include "algorithms/keypoints/segment_displacement.hpp"

namespace tlsmon {

struct KeypointScanReference {
    keypoints::Features features;  // kept keypoints, their descriptors row by row
    std::vector<keypoints::AngularPosition> positions;  // lattice angles, per keypoint
    // Where each keypoint is measured: its own sub-pixel position, or with refinement the
    // pixel nearest it (an exact return) whose intensity patch is sought in the epoch.
    std::vector<double> anchor_rows, anchor_columns;
    std::vector<keypoints::Polar> polar;  // scanner frame, at the anchor
    std::vector<Eigen::Vector3d> points;  // project frame, at the anchor
    std::vector<float> patches;           // (2·radius + 1)² intensities per keypoint
    double angular_step = 0;   // rad, the larger of the images' horizontal and vertical steps
    std::size_t detected = 0;  // keypoints detected (before description and 3-D)

    std::size_t size() const { return features.keypoints.size(); }
};

struct KeypointReference {
    static constexpr int kFormatVersion = 5;
    static constexpr const char* kStage = "keypoints";

    std::vector<KeypointScanReference> scans;           // the structured scans, in file order
    int patch_radius = 0;                               // 0: no patches (no refinement)
    double prefilter_px = 0;                            // the patches' Gaussian prefilter, px
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();  // the reference scan's position
    std::vector<std::string> zone_names;                // zones mode, in the configuration's order
    std::vector<keypoints::WallFrame> walls;            // per zone, from the reference's points
    // Per zone, the vertical angle of each wall cell the reference saw (zone_strata.hpp).
    std::vector<std::vector<float>> wall_cells;
    double seconds = 0;  // time it took to build

    std::size_t keypoints() const;  // kept, over every scan
    std::size_t detected() const;

    std::string encode() const;
    static KeypointReference decode(std::string_view payload);
};

}  // namespace tlsmon
