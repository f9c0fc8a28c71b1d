#include "algorithms/zones/zone_shape.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tlsmon {

namespace {

// "10", "12.5": a limit as a name shows it.
std::string limit_text(double v) {
    std::ostringstream s;
    s << (std::abs(v) < 1e-12 ? 0.0 : v);
    return s.str();
}

// Twice the signed area (shoelace formula).
double twice_area(const std::vector<Eigen::Vector2d>& p) {
    double a = 0;
    for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
        a += p[j].x() * p[i].y() - p[i].x() * p[j].y();
    }
    return a;
}

}  // namespace

bool inside_polygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& q) {
    bool inside = false;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
        const Eigen::Vector2d& a = polygon[j];
        const Eigen::Vector2d& b = polygon[i];
        // On the edge a-b: collinear and between its ends.
        const Eigen::Vector2d ab = b - a, aq = q - a;
        const double cross = ab.x() * aq.y() - ab.y() * aq.x();
        if (std::abs(cross) <= 1e-12 * std::max(1.0, ab.squaredNorm()) && aq.dot(q - b) <= 0.0) {
            return true;
        }
        // Crossing of the ray towards +x (half-open in y: each vertex counted once).
        if ((a.y() > q.y()) != (b.y() > q.y())) {
            const double x = a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
            if (q.x() < x) inside = !inside;
        }
    }
    return inside;
}

bool ZoneShape::contains(const Eigen::Vector3d& p) const {
    if (!box.contains(p)) return false;
    return polygon.empty() || inside_polygon(polygon, p.head<2>());
}

ZoneShape box_zone(std::string name, const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
    if (!(min.array() < max.array()).all()) {
        throw Error("zone '" + name + "': each coordinate of max must exceed the one of min");
    }
    return ZoneShape{std::move(name), Eigen::AlignedBox3d(min, max), {}};
}

ZoneShape prism_zone(std::string name, std::vector<Eigen::Vector2d> polygon, double z_min,
                     double z_max) {
    if (polygon.size() < 3) {
        throw Error("zone '" + name + "': a polygon needs at least 3 vertices");
    }
    for (const auto& v : polygon) {
        if (!v.allFinite()) throw Error("zone '" + name + "': a polygon vertex is not finite");
    }
    if (!(std::abs(twice_area(polygon)) > 0.0)) {
        throw Error("zone '" + name + "': the polygon has no area");
    }
    if (!(z_min < z_max)) throw Error("zone '" + name + "': z max must exceed z min");
    Eigen::AlignedBox2d xy;
    for (const auto& v : polygon) xy.extend(v);
    ZoneShape s;
    s.name = std::move(name);
    s.box = Eigen::AlignedBox3d(Eigen::Vector3d(xy.min().x(), xy.min().y(), z_min),
                                Eigen::Vector3d(xy.max().x(), xy.max().y(), z_max));
    s.polygon = std::move(polygon);
    return s;
}

std::vector<ZoneShape> bands_of(const ZoneShape& base, int axis, double height, double from,
                                double to) {
    if (axis < 0 || axis > 2) throw Error("zone bands: the axis is x, y or z");
    if (!(std::isfinite(height) && height > 0.0)) {
        throw Error("zone bands of '" + base.name + "': the band height must be positive");
    }
    if (!(std::isfinite(from) && std::isfinite(to) && from < to)) {
        throw Error("zone bands of '" + base.name + "': the range must be from < to");
    }
    if ((to - from) / height > 10000) {
        throw Error("zone bands of '" + base.name + "': more than 10000 bands");
    }
    std::vector<ZoneShape> out;
    for (int k = 0;; ++k) {
        const double a = from + k * height;
        if (!(a < to - 1e-9 * height)) break;
        const double b = std::min(to, from + (k + 1) * height);
        ZoneShape band = base;
        band.name = base.name + " " + limit_text(a) + "–" + limit_text(b) + " m";
        band.box.min()[axis] = std::max(base.box.min()[axis], a);
        band.box.max()[axis] = std::min(base.box.max()[axis], b);
        if (!(band.box.min()[axis] < band.box.max()[axis])) continue;  // outside the base
        out.push_back(std::move(band));
    }
    if (out.empty()) {
        throw Error("zone bands of '" + base.name + "': no band overlaps the zone");
    }
    return out;
}

}  // namespace tlsmon
