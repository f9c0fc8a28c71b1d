#include "simulator/ray_cast.hpp"

#include <cmath>

#include "simulator/deformation.hpp"
#include "simulator/texture.hpp"

namespace tlsmon::sim {

namespace {

constexpr double kSphereAlbedo = 0.85;  // white matte target sphere

struct BoxHit {
    double t = std::numeric_limits<double>::infinity();
    int axis = -1;     // 0 x, 1 y, 2 z
    bool low = false;  // entered through the low face of that axis
};

// Slab method (Kay & Kajiya 1986): entry distance into an axis-aligned box.
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

int pier_face(const BoxHit& h) {
    if (h.axis == 0) return h.low ? 0 : 1;
    if (h.axis == 1) return h.low ? 2 : 3;
    return 4;
}

// Face coordinates (u along the face, v up) of a point on face f.
Eigen::Vector2d face_uv(int face, const Eigen::Vector3d& p) {
    switch (face) {
        case 0:
        case 1:
            return {p.y(), p.z()};
        case 2:
        case 3:
            return {p.x(), p.z()};
        default:
            return {p.x(), p.y()};
    }
}

void consider(Hit& best, const Hit& h) {
    if (h.range < best.range) best = h;
}

}  // namespace

SceneAtEpoch::SceneAtEpoch(const Site& s, int e, double h)
    : SceneAtEpoch(s, epoch_conditions(s, e, h)) {}

SceneAtEpoch::SceneAtEpoch(const Site& s, const EpochConditions& c)
    : site(&s), epoch(c.epoch), hours(c.hours), displacement(s, c.epoch, c.bending) {
    const int e = c.epoch;
    for (std::size_t i = 0; i < s.targets.size(); ++i) {
        const Eigen::Vector3d c = target_centre(s, i, e);
        target_centres.push_back(c);
        // Planar targets are set up facing the station (horizontal normal towards it).
        Eigen::Vector3d n = s.scanner.position - s.targets[i].centre;
        n.z() = 0.0;
        target_normals.push_back(n.norm() > 0 ? n.normalized() : Eigen::Vector3d::UnitY());
    }
    // A bound on |u| at this epoch ((z/H)^p <= 1), plus 1 mm.
    if (s.deformation.enabled) pier_reach += c.bending.top.norm();
    if (s.events.step_epoch >= 0 && e >= s.events.step_epoch) {
        pier_reach += s.events.step_displacement.norm();
    }
}

Hit cast_ray(const SceneAtEpoch& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
             double max_range) {
    const Site& site = *scene.site;
    Hit best;
    best.range = max_range;

    // Ground plane z = 0.
    if (d.z() < 0.0) {
        const double t = -o.z() / d.z();
        if (t > 0.0 && t < best.range) {
            const Eigen::Vector3d p = o + t * d;
            consider(best, {Surface::ground, t, Eigen::Vector3d::UnitZ(),
                            ground_albedo(site.texture, p.x(), p.y()), -1});
        }
    }

    // Pier: each face is its displaced surface {q + u(q) : q on the face}; the nearest
    // front-facing intersection whose material point lies on the face is the hit (see header).
    const Pier& pier = site.pier;
    const Eigen::Vector3d lo(pier.x0, pier.y0, 0.0), hi(pier.x1, pier.y1, pier.height);
    const Eigen::Vector3d reach = Eigen::Vector3d::Constant(scene.pier_reach);
    if (intersect_box(lo - reach, hi + reach, o, d).axis >= 0) {
        for (int face = 0; face < 5; ++face) {
            const int axis = face / 2;
            const bool low = face == 0 || face == 2;
            Eigen::Vector3d n = Eigen::Vector3d::Zero();
            n[axis] = low ? -1.0 : 1.0;
            const double dn = d.dot(n);
            if (dn > -1e-12) continue;  // seen from behind or edge-on
            double t = ((low ? lo : hi)[axis] - o[axis]) / d[axis];
            Eigen::Vector3d q = o + t * d;
            for (int pass = 0; pass < 20; ++pass) {
                const Eigen::Vector3d u = scene.displacement(q);
                const double next = n.dot(q + u - o) / dn;
                q = o + next * d - u;
                const bool converged = std::abs(next - t) < 1e-9;
                t = next;
                if (converged) break;
            }
            if (!(t > 0.0 && t < best.range)) continue;
            bool on_face = true;
            for (int a = 0; a < 3; ++a) {
                if (a != axis && (q[a] < lo[a] || q[a] > hi[a])) on_face = false;
            }
            if (!on_face) continue;
            const Eigen::Vector2d uv = face_uv(face, q);
            consider(best, {Surface::pier, t, n,
                            concrete_albedo(site.texture, face, uv.x(), uv.y()), -1, face, uv});
        }
    }

    // Deck (not deformed).
    if (site.deck.enabled) {
        const Deck& k = site.deck;
        const double cy = 0.5 * (pier.y0 + pier.y1);
        const BoxHit dh = intersect_box(
            {pier.x0 - k.overhang, cy - k.half_length, pier.height},
            {pier.x1 + k.overhang, cy + k.half_length, pier.height + k.thickness}, o, d);
        if (dh.axis >= 0 && dh.t < best.range) {
            Eigen::Vector3d n = Eigen::Vector3d::Zero();
            n[dh.axis] = dh.low ? -1.0 : 1.0;
            const Eigen::Vector3d p = o + dh.t * d;
            const int face = 5 + pier_face(dh);
            const Eigen::Vector2d uv = face_uv(pier_face(dh), p);
            consider(best, {Surface::deck, dh.t, n,
                            concrete_albedo(site.texture, face, uv.x(), uv.y()), -1, face, uv});
        }
    }

    // Targets.
    for (std::size_t i = 0; i < site.targets.size(); ++i) {
        const Target& tg = site.targets[i];
        const Eigen::Vector3d& c = scene.target_centres[i];
        if (tg.kind == Target::Kind::sphere) {
            // |o + t d − c|² = r²  ->  t = −b − sqrt(b² − (|o − c|² − r²)), b = d·(o − c).
            const Eigen::Vector3d oc = o - c;
            const double b = d.dot(oc);
            const double disc = b * b - (oc.squaredNorm() - tg.radius * tg.radius);
            if (disc < 0.0) continue;
            const double t = -b - std::sqrt(disc);
            if (t <= 0.0 || t >= best.range) continue;
            const Eigen::Vector3d p = o + t * d;
            consider(best,
                     {Surface::sphere, t, (p - c) / tg.radius, kSphereAlbedo, static_cast<int>(i)});
        } else {
            const Eigen::Vector3d& n = scene.target_normals[i];
            const double dn = d.dot(n);
            if (std::abs(dn) < 1e-12) continue;
            const double t = n.dot(c - o) / dn;
            if (t <= 0.0 || t >= best.range) continue;
            const Eigen::Vector3d p = o + t * d - c;
            const Eigen::Vector3d horizontal(-n.y(), n.x(), 0.0);
            const double a = p.dot(horizontal), b = p.z();
            const double half = 0.5 * tg.size;
            if (std::abs(a) > half || std::abs(b) > half) continue;
            // 2x2 checkerboard (texture.hpp): white where both coordinates have the same sign.
            Hit h{Surface::checkerboard, t, n, checkerboard_albedo(a, b), static_cast<int>(i)};
            h.uv = {a, b};
            consider(best, h);
        }
    }
    if (best.surface == Surface::none) best.range = std::numeric_limits<double>::infinity();
    return best;
}

}  // namespace tlsmon::sim
