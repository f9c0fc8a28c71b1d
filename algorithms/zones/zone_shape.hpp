#pragma once
// A zone's shape: the named region of the structure whose core points (or keypoints) one
// time series aggregates. A box (axis-aligned, project frame), or a prism (a polygon in x, y
// and a z range); a band cuts a shape into slices along an axis ("south face 10–20 m").
// Every shape has a bounding box: the registration's σ at a zone is taken at its corners
// (pipeline/registration_stage.hpp), which for a prism or a band bounds it from above.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <string>
#include <vector>

namespace tlsmon {

struct ZoneShape {
    std::string name;
    // The box; for a prism the polygon's bounds in x, y and its z range. A point is inside
    // when it is inside the box (boundaries included) and, for a prism, inside the polygon.
    Eigen::AlignedBox3d box;
    std::vector<Eigen::Vector2d> polygon;  // empty: a box
    // The design normal of the planar face the zone covers (unit length), used by M3C2 at
    // the zone's core points instead of an estimate; NaN: estimated (docs/m3c2.md).
    Eigen::Vector3d normal = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());

    bool contains(const Eigen::Vector3d& p) const;
    const Eigen::AlignedBox3d& bounds() const { return box; }
};

ZoneShape box_zone(std::string name, const Eigen::Vector3d& min, const Eigen::Vector3d& max);
// A prism: `polygon` (x, y; at least 3 vertices, either orientation, not self-intersecting)
// between z_min and z_max. Throws Error for a degenerate polygon or z range.
ZoneShape prism_zone(std::string name, std::vector<Eigen::Vector2d> polygon, double z_min,
                     double z_max);

// Whether (x, y) lies inside the polygon or on its boundary (even-odd rule; a point on an
// edge counts as inside).
bool inside_polygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& q);

// The bands of `base` along axis 0 (x), 1 (y) or 2 (z): slices [from + k·height,
// from + (k + 1)·height] ∩ base for k = 0, 1, … while the slice starts below `to`, the
// last one cut at `to`; named "<base> A–B m" (A, B the slice's limits along the axis,
// shortest decimal form). Throws Error for a height ≤ 0 or an empty range.
std::vector<ZoneShape> bands_of(const ZoneShape& base, int axis, double height, double from,
                                double to);

}  // namespace tlsmon
