#include "simulator/target_layout.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/angles.hpp"
#include "core/error.hpp"
#include "simulator/terrain.hpp"

namespace tlsmon::sim {

namespace {

double base_at(const Site& site, const std::string& name, Target::Mount mount, double x, double y) {
    int block = -1;
    const double z = support_height(site.terrain, x, y, &block);
    if (mount == Target::Mount::abutment && block < 0) {
        throw Error("target '" + name + "' is mounted on an abutment but no block lies under (" +
                    std::to_string(x) + ", " + std::to_string(y) + ")");
    }
    return z;
}

}  // namespace

Target place_target(const Site& site, const TargetPlacement& p) {
    Target t;
    t.name = p.name;
    t.kind = p.kind;
    t.radius = p.radius;
    t.size = p.size;
    t.mount = p.mount;
    const Eigen::Vector3d s = site.scanner.position;
    const double a = (p.azimuth_deg + site.scanner.heading_deg) * kDeg;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    double distance = p.distance;
    if (p.range > 0.0) {
        // range² = distance² + (z(distance) − z_s)²: a fixed point, z varies slowly.
        distance = p.range;
        for (int k = 0; k < 50; ++k) {
            const Eigen::Vector2d xy = s.head<2>() + distance * dir;
            const double dz = base_at(site, p.name, p.mount, xy.x(), xy.y()) + p.height - s.z();
            if (std::abs(dz) >= p.range) {
                throw Error("target '" + p.name + "': range shorter than its height difference");
            }
            distance = std::sqrt(p.range * p.range - dz * dz);
        }
    }
    if (!(distance > 0.0)) throw Error("target '" + p.name + "': distance or range must be > 0");
    const Eigen::Vector2d xy = s.head<2>() + distance * dir;
    t.base_z = base_at(site, p.name, p.mount, xy.x(), xy.y());
    t.centre = {xy.x(), xy.y(), t.base_z + p.height};
    return t;
}

double target_base_z(const Site& site, const Target& t) {
    return base_at(site, t.name, t.mount, t.centre.x(), t.centre.y());
}

std::vector<Cylinder> target_supports(const Target& t, const Eigen::Vector3d& c,
                                      const Eigen::Vector3d& normal) {
    std::vector<Cylinder> parts;
    if (t.mount == Target::Mount::none) return parts;
    const bool sphere = t.kind == Target::Kind::sphere;
    const double r = t.mount == Target::Mount::stand ? kStandPoleRadius : kMastRadius;
    // The pole stands under the sphere (its top inside it) or behind the board's centre.
    Eigen::Vector3d foot(c.x(), c.y(), t.base_z), top = c;
    if (sphere) {
        top.z() = c.z() - std::sqrt(std::max(t.radius * t.radius - r * r, 0.0));
    } else {
        foot -= kBoardPoleOffset * normal;
        top -= kBoardPoleOffset * normal;
    }
    if (top.z() <= foot.z()) return parts;
    parts.push_back({foot, top, r});
    if (t.mount != Target::Mount::stand) return parts;
    const double h = top.z() - foot.z();
    const Eigen::Vector3d head = foot + Eigen::Vector3d(0.0, 0.0, 0.6 * h);
    const double facing = std::atan2(normal.y(), normal.x());
    for (const double leg_deg : {90.0, 210.0, 330.0}) {
        const double b = facing + leg_deg * kDeg;
        const Eigen::Vector3d ground =
            foot + 0.45 * h * Eigen::Vector3d(std::cos(b), std::sin(b), 0.0);
        parts.push_back({head, ground, kStandLegRadius});
    }
    return parts;
}

const char* mount_name(Target::Mount m) {
    switch (m) {
        case Target::Mount::mast:
            return "mast";
        case Target::Mount::stand:
            return "stand";
        case Target::Mount::abutment:
            return "abutment";
        default:
            return "none";
    }
}

}  // namespace tlsmon::sim
