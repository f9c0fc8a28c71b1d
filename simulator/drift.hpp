#pragma once
// Scanner instability per epoch: the tripod's head turns slowly about the standing axis
// (thermal and settling effects, tens of arc seconds over a day), tilts slightly and moves
// by fractions of a millimetre. The PTX header keeps the nominal set-up pose; the points
// are measured from the disturbed pose, so coordinates taken through the header are off by
// exactly this error, which registration on the targets must remove.
#include <Eigen/Geometry>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct PoseError {
    double yaw = 0.0;     // rad, about the scanner's z (standing axis)
    double tilt_x = 0.0;  // rad, about the scanner's x
    double tilt_y = 0.0;  // rad, about the scanner's y
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // m, scanner frame

    // E in scanner frame: p_true_scanner = E · p_measured. E = T(translation)·Rz·Ry·Rx.
    Eigen::Affine3d transform() const;
};

// Smooth part: yaw = A·sin(2π t / period), tilt_x = B·sin(2π t / period), tilt_y =
// B·(1 − cos(2π t / period)) / 2; plus Gaussian jitter and translation seeded from
// (noise.seed, epoch); from events.station_change_epoch on, the station change added. Zero
// when drift is disabled and the station never changed.
PoseError pose_error(const Site& site, int epoch, double hours);

// Nominal scanner -> project transform N (position and heading): what the header says.
Eigen::Affine3d nominal_pose(const Scanner& scanner);

}  // namespace tlsmon::sim
