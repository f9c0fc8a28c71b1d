#pragma once
// Fixed-radius neighbours in an unstructured cloud (a campaign's PLS or MLS cloud has no scan
// grid to look along): the points bucketed on a uniform grid of cubic cells, each cell's
// points contiguous. A query visits the cells its sphere's bounding cube touches and tests
// their points exactly; with cells no smaller than the radius that is at most 27 cells.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

namespace tlsmon::campaign {

class PointGrid {
  public:
    // Points that are not finite are left out of every query.
    PointGrid(std::span<const Eigen::Vector3d> points, double cell);

    // visit(index, squared distance) for every point within `radius` of c.
    template <class Visit>
    void within(const Eigen::Vector3d& c, double radius, Visit&& visit) const {
        const double r2 = radius * radius;
        const Eigen::Vector3d lo = (c.array() - radius) / cell_, hi = (c.array() + radius) / cell_;
        for (long z = long(std::floor(lo.z())); z <= long(std::floor(hi.z())); ++z)
            for (long y = long(std::floor(lo.y())); y <= long(std::floor(hi.y())); ++y)
                for (long x = long(std::floor(lo.x())); x <= long(std::floor(hi.x())); ++x) {
                    const auto it = cells_.find(key(x, y, z));
                    if (it == cells_.end()) continue;
                    for (std::uint32_t k = it->second.first; k < it->second.second; ++k) {
                        const std::uint32_t i = order_[k];
                        const double d2 = (points_[i] - c).squaredNorm();
                        if (d2 <= r2) visit(i, d2);
                    }
                }
    }

    double cell() const { return cell_; }

  private:
    // Cell coordinates packed into 21 bits each (±2^20 cells: ±1000 km at 1 m cells).
    static std::uint64_t key(long x, long y, long z) {
        constexpr long kOffset = 1L << 20;
        return (std::uint64_t(x + kOffset) & 0x1FFFFF) |
               ((std::uint64_t(y + kOffset) & 0x1FFFFF) << 21) |
               ((std::uint64_t(z + kOffset) & 0x1FFFFF) << 42);
    }
    std::span<const Eigen::Vector3d> points_;
    double cell_;
    std::vector<std::uint32_t> order_;  // point indices, cell by cell
    std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> cells_;
};

}  // namespace tlsmon::campaign
