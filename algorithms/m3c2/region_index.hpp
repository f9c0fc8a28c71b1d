#pragma once
// Fixed-radius queries turned around. M3C2 asks, at every core point, which points of a cloud
// lie in a small region around it (a sphere for the normal, a cylinder for the distance).
// Instead of indexing the cloud (millions of points, a new tree for every epoch), this indexes
// the regions of the core points (tens of thousands, built once from the reference) on a
// uniform grid of cells, and streams the cloud through it: each point looks up its one cell
// and is tested exactly against the few regions that may reach into that cell. A new epoch
// then needs no search structure of its own and no copy of its points.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace tlsmon::m3c2 {

class RegionIndex {
  public:
    RegionIndex() = default;

    // Spheres of `radius` around `centres` (all of them).
    static RegionIndex spheres(const std::vector<Eigen::Vector3d>& centres, double radius,
                               double cell, unsigned threads = 0);
    // Cylinders around `centres` with axes `axes` (unit vectors; a centre whose axis is not
    // finite has no cylinder), radius and half-length along the axis.
    static RegionIndex cylinders(const std::vector<Eigen::Vector3d>& centres,
                                 const std::vector<Eigen::Vector3d>& axes, double radius,
                                 double half_length, double cell, unsigned threads = 0);

    // The cell of p as a key, or nullopt when p is not finite or far outside every region.
    std::optional<std::uint64_t> key_of(const Eigen::Vector3d& p) const;
    // The regions (indices of centres, ascending) that may contain a point of this cell: a
    // superset of those that do, to be tested exactly by the caller.
    std::span<const std::uint32_t> regions_in(std::uint64_t key) const;

    // The box around the region of centre k (empty for a centre without a region).
    const Eigen::AlignedBox3d& box(std::size_t k) const { return boxes_[k]; }

    std::size_t cells() const { return cell_begin_.empty() ? 0 : cell_begin_.size() - 1; }
    std::size_t entries() const { return regions_.size(); }
    double cell() const { return cell_; }

  private:
    template <class Extent, class Reaches>
    void build(std::size_t n, Extent&& extent, Reaches&& reaches, unsigned threads);

    struct Slot {
        std::uint64_t key;
        std::uint32_t cell;
    };
    double cell_ = 1.0;
    double inverse_cell_ = 1.0;
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
    std::vector<Slot> table_;  // open addressing, power-of-two size, linear probing
    std::uint64_t mask_ = 0;
    std::vector<std::uint64_t> cell_begin_;  // per cell, into regions_; one past the last
    std::vector<std::uint32_t> regions_;
    std::vector<Eigen::AlignedBox3d> boxes_;
};

}  // namespace tlsmon::m3c2
