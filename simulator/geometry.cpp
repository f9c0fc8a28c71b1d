#include "simulator/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace tlsmon::sim {

BoxHit intersect_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
                     const Eigen::Vector3d& d) {
    double t_in = -std::numeric_limits<double>::infinity();
    double t_out = std::numeric_limits<double>::infinity();
    BoxHit h;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-15) {
            if (o[a] < lo[a] || o[a] > hi[a]) return {};
            continue;
        }
        double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
        bool low = true;
        if (t0 > t1) {
            std::swap(t0, t1);
            low = false;
        }
        if (t0 > t_in) {
            t_in = t0;
            h.axis = a;
            h.low = low;
        }
        t_out = std::min(t_out, t1);
    }
    if (t_in > t_out || t_in <= 0.0) return {};
    h.t = t_in;
    return h;
}

bool box_interval(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
                  const Eigen::Vector3d& d, double t_max, double& t_in, double& t_out) {
    t_in = 0.0;
    t_out = t_max;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-15) {
            if (o[a] < lo[a] || o[a] > hi[a]) return false;
            continue;
        }
        const double inv = 1.0 / d[a];
        double t0 = (lo[a] - o[a]) * inv, t1 = (hi[a] - o[a]) * inv;
        if (t0 > t1) std::swap(t0, t1);
        t_in = std::max(t_in, t0);
        t_out = std::min(t_out, t1);
        if (t_in > t_out) return false;
    }
    return true;
}

double intersect_sphere(const Eigen::Vector3d& c, double r, const Eigen::Vector3d& o,
                        const Eigen::Vector3d& d) {
    // t = −b − sqrt(b² − (|o − c|² − r²)), b = d·(o − c).
    const Eigen::Vector3d oc = o - c;
    const double b = d.dot(oc);
    const double disc = b * b - (oc.squaredNorm() - r * r);
    if (disc < 0.0) return kNoHit;
    const double t = -b - std::sqrt(disc);
    return t > 0.0 ? t : kNoHit;
}

double intersect_cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                          const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                          Eigen::Vector3d& normal) {
    const Eigen::Vector3d axis = b - a;
    const double length = axis.norm();
    if (length <= 0.0) return kNoHit;
    const Eigen::Vector3d w = axis / length;
    // Components perpendicular to the axis: |(o − a)⊥ + t d⊥|² = r².
    const Eigen::Vector3d oa = o - a;
    const Eigen::Vector3d dp = d - d.dot(w) * w, op = oa - oa.dot(w) * w;
    double best = kNoHit;
    const double qa = dp.squaredNorm();
    if (qa > 1e-18) {
        const double qb = dp.dot(op), qc = op.squaredNorm() - r * r;
        const double disc = qb * qb - qa * qc;
        if (disc >= 0.0) {
            const double t = (-qb - std::sqrt(disc)) / qa;
            const double s = oa.dot(w) + t * d.dot(w);  // along the axis
            if (t > 0.0 && s >= 0.0 && s <= length) {
                best = t;
                normal = (op + t * dp) / r;
            }
        }
    }
    // Caps: the planes through a and b normal to the axis, within radius r.
    const double dw = d.dot(w);
    if (std::abs(dw) > 1e-15) {
        for (const bool top : {false, true}) {
            const Eigen::Vector3d& c = top ? b : a;
            const double t = (c - o).dot(w) / dw;
            if (!(t > 0.0 && t < best)) continue;
            if ((o + t * d - c).squaredNorm() > r * r) continue;
            best = t;
            normal = top ? w : Eigen::Vector3d(-w);
        }
    }
    return best;
}

}  // namespace tlsmon::sim
