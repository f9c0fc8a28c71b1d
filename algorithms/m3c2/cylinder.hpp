#pragma once
// The projection cylinder of M3C2 (Lague 2013, step 2: a cylinder of diameter d and maximum
// depth along the normal, in which each cloud's points are projected on the normal). As
// pinned by the tests and docs/m3c2.md: the points p with |(p - c) . n| <= max_depth and
// |(p - c) - ((p - c) . n) n| <= radius; the statistic of the projections (p - c) . n is
// their mean with the sample standard deviation (n - 1), or their median with the
// interquartile range (quantiles by linear interpolation between order statistics, at
// position (n - 1) q).
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "algorithms/m3c2/parameters.hpp"
#include "algorithms/m3c2/region_index.hpp"

namespace tlsmon::m3c2 {

inline bool in_cylinder(const Eigen::Vector3d& p, const Eigen::Vector3d& c,
                        const Eigen::Vector3d& n, double radius, double max_depth) {
    const Eigen::Vector3d d = p - c;
    const double along = d.dot(n);
    if (!(std::abs(along) <= max_depth)) return false;
    return (d - along * n).norm() <= radius;
}

// One cloud's side of the distance at one core point.
struct CylinderSide {
    double centre = std::numeric_limits<double>::quiet_NaN();  // mean or median projection
    double spread = std::numeric_limits<double>::quiet_NaN();  // std (n - 1) or IQR
    std::uint32_t count = 0;                                   // points in the cylinder
    // The spread of all its points, strays included: what max_roughness asks of the
    // reference, so that an edge is refused as in the published method even when the strays'
    // removal would leave one face.
    double roughness = std::numeric_limits<double>::quiet_NaN();
    // Where in the cylinder its points lie: their mean offset from the axis, across it, and
    // their RMS distance from the axis. An epoch that saw part of what the reference saw there
    // has its offset elsewhere (distance_between).
    Eigen::Vector3d lateral = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    double lateral_spread = std::numeric_limits<double>::quiet_NaN();
};

// The lateral and lateral_spread of the points `members` of `cloud` in the cylinder at c
// with axis n.
void set_lateral(CylinderSide& side, const std::vector<Eigen::Vector3d>& cloud,
                 std::span<const std::uint32_t> members, const Eigen::Vector3d& c,
                 const Eigen::Vector3d& n);

// The statistic of projections (reordered in place for the median). With the mean and a
// finite `stray_distance`, the projections farther from their median than both
// stray_distance and kStrayRobustSigmas robust σ (kMadToSigma·MAD) are removed first, and
// `count` is of those kept; when they were more than kMaxStrayShare of the points, centre and
// spread are NaN (two surfaces). Centre NaN without points, spread NaN with fewer than 2.
// `roughness` is the spread before any removal.
CylinderSide statistic_of(std::vector<double>& projections, CylinderStatistic statistic,
                          double stray_distance = std::numeric_limits<double>::infinity());

// The cylinders of a set of core points: where they are, their axes (NaN: no normal, no
// cylinder) and the index that finds the cylinders a point may lie in.
struct Cylinders {
    std::vector<Eigen::Vector3d> centres;
    std::vector<Eigen::Vector3d> axes;
    CylinderParameters parameters;
    RegionIndex index;
};

Cylinders make_cylinders(std::vector<Eigen::Vector3d> centres, std::vector<Eigen::Vector3d> axes,
                         const CylinderParameters& parameters, unsigned threads = 0);

// One cloud's side at every core point (the reference's once, each epoch's), parallel over
// core points; the cloud is streamed through the cylinders' index, never copied or indexed.
// `left_out`: empty, or per point of the cloud non-zero for one no cylinder takes.
std::vector<CylinderSide> cylinder_sides(const Cylinders& cylinders,
                                         const std::vector<Eigen::Vector3d>& cloud,
                                         unsigned threads = 0,
                                         std::span<const std::uint8_t> left_out = {});

}  // namespace tlsmon::m3c2
