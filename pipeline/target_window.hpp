#pragma once
// The points of a scan near one predicted position, taken through the structured grid: the
// points of a structured scan are stored column by column, row by row within a column (PTX;
// the simulator's scans), so the azimuth of the points is monotone along the file and the
// elevation monotone within a column. Binary searches find the columns within the angular
// window about the predicted direction and, in each, the rows: O(columns · log n), never a
// pass over all points. A scan without a grid (or whose order breaks that rule) is searched
// point by point, which the result says.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

struct TargetWindow {
    std::vector<std::size_t> indices;  // points within `radius` of the predicted position
    bool through_grid = false;         // false: every point was looked at
    std::size_t examined = 0;          // points whose distance was computed
};

// The points of `scan` (project frame) within `radius` (m) of `predicted` (project frame).
TargetWindow points_near(const Scan& scan, const Eigen::Vector3d& predicted, double radius);

}  // namespace tlsmon
