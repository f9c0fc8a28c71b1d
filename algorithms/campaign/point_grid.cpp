#include "algorithms/campaign/point_grid.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace tlsmon::campaign {

PointGrid::PointGrid(std::span<const Eigen::Vector3d> points, double cell)
    : points_(points), cell_(cell) {
    if (!(cell > 0)) throw Error("campaign: a point grid needs a positive cell size");
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
    keyed.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) continue;
        const Eigen::Vector3d q = points[i] / cell;
        keyed.emplace_back(
            key(long(std::floor(q.x())), long(std::floor(q.y())), long(std::floor(q.z()))),
            std::uint32_t(i));
    }
    std::sort(keyed.begin(), keyed.end());
    order_.reserve(keyed.size());
    for (std::size_t k = 0; k < keyed.size();) {
        std::size_t j = k;
        while (j < keyed.size() && keyed[j].first == keyed[k].first)
            order_.push_back(keyed[j++].second);
        cells_.emplace(keyed[k].first, std::pair{std::uint32_t(k), std::uint32_t(j)});
        k = j;
    }
}

}  // namespace tlsmon::campaign
