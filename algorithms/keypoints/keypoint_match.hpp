#pragma once
// One reference keypoint matched in an epoch: where it lies in both spherical images and the
// 3-D points both give, in the project frame (the epoch's point after its registration).
// The matching (images, detector, descriptor) produces these; the outlier filters, the
// per-segment displacements and the displacement model consume them.
#include <Eigen/Core>

namespace tlsmon::keypoints {

struct KeypointMatch {
    // Sub-pixel image positions (row = vertical angle step, column = horizontal angle step).
    double reference_row = 0, reference_column = 0;
    double row = 0, column = 0;
    // Scanner-frame polar coordinates at the keypoint: range (m), horizontal and vertical
    // angle (rad).
    double reference_range = 0, range = 0;
    double reference_azimuth = 0, azimuth = 0;
    double reference_elevation = 0, elevation = 0;
    Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();  // project frame, m
    Eigen::Vector3d point = Eigen::Vector3d::Zero();            // project frame, m
    double descriptor_distance = 0;                             // Hamming or L2
    int segment = -1;  // the segment (zone or vertical-angle band) it falls in; -1: none
    int scan = 0;      // which structured scan of the file measured it (0: the first)

    Eigen::Vector3d displacement() const { return point - reference_point; }
};

}  // namespace tlsmon::keypoints
