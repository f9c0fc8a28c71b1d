#pragma once
// The extent of a point cloud: its axis-aligned bounding box, and how much of another cloud
// lies within it. Used to see that an epoch covers the same part of the site as the
// reference epoch (a scanner knocked off its aim, or a scan cut short, does not).
#include <Eigen/Core>
#include <limits>
#include <vector>

namespace tlsmon {

struct BoundingBox {
    Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

    bool empty() const { return !(min.array() <= max.array()).all(); }
    void extend(const Eigen::Vector3d& p) {
        min = min.cwiseMin(p);
        max = max.cwiseMax(p);
    }
    // Inside the box grown by `margin` on every side (boundary included).
    bool contains(const Eigen::Vector3d& p, double margin = 0.0) const {
        return ((p.array() >= min.array() - margin) && (p.array() <= max.array() + margin)).all();
    }
};

BoundingBox bounding_box(const std::vector<Eigen::Vector3d>& points);

// The share (0..1) of `points` inside `box` grown by `margin`; NaN for no points.
double share_inside(const std::vector<Eigen::Vector3d>& points, const BoundingBox& box,
                    double margin);

}  // namespace tlsmon
