#include "algorithms/extent.hpp"

#include <cstddef>

namespace tlsmon {

BoundingBox bounding_box(const std::vector<Eigen::Vector3d>& points) {
    BoundingBox box;
    for (const auto& p : points) box.extend(p);
    return box;
}

double share_inside(const std::vector<Eigen::Vector3d>& points, const BoundingBox& box,
                    double margin) {
    if (points.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::size_t inside = 0;
    for (const auto& p : points) inside += box.contains(p, margin) ? 1 : 0;
    return static_cast<double>(inside) / static_cast<double>(points.size());
}

}  // namespace tlsmon
