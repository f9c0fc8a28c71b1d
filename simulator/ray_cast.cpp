#include "simulator/ray_cast.hpp"

#include <algorithm>
#include <cmath>

#include "simulator/deformation.hpp"
#include "simulator/geometry.hpp"
#include "simulator/terrain.hpp"
#include "simulator/texture.hpp"

namespace tlsmon::sim {

namespace {

constexpr double kSphereAlbedo = 0.85;  // white matte target sphere
constexpr double kMastAlbedo = 0.55;    // painted steel or aluminium tube

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

// Can the ray o + t·d (d unit, 0 < t < t_max) pass within `radius` of `centre`? Cheaper
// than a slab test: the first cull for the small objects (targets, occluders).
bool near_ray(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& o,
              const Eigen::Vector3d& d, double t_max) {
    const Eigen::Vector3d v = centre - o;
    const double along = v.dot(d);
    if (along < -radius || along > t_max + radius) return false;
    return v.squaredNorm() - along * along <= radius * radius;
}

void consider(Hit& best, const Hit& h) {
    if (h.range < best.range) best = h;
}

// The round pier's displaced surface {q + u(q) : q on the cylinder}: the cylinder moved by
// u at the current material point, intersected, the material point updated, until the range
// settles (u varies by micrometres across a beam's step). One face (0); (u, v) = (r·φ, z).
Hit cast_round_pier(const SceneAtEpoch& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    const Pier& pier = scene.site->pier;
    const double r = 0.5 * pier.diameter;
    const Eigen::Vector2d c = pier.centre();
    const Eigen::Vector3d foot(c.x(), c.y(), 0.0), top(c.x(), c.y(), pier.height);
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), n, q;
    double t = kNoHit;
    for (int pass = 0; pass < 20; ++pass) {
        const double next = intersect_cylinder(foot + u, top + u, r, o, d, n);
        if (next == kNoHit) return {};
        q = o + next * d - u;
        u = scene.displacement(q);
        const bool converged = std::abs(next - t) < 1e-9;
        t = next;
        if (converged) break;
    }
    const Eigen::Vector2d uv(r * std::atan2(q.y() - c.y(), q.x() - c.x()), q.z());
    return {
        Surface::pier, t, n, concrete_albedo(scene.site->texture, 0, uv.x(), uv.y()), -1, 0, uv};
}

}  // namespace

const char* surface_name(Surface s) {
    static constexpr const char* names[kSurfaceKinds] = {
        "none",     "ground", "pier",  "deck",     "sphere",     "checkerboard", "foundation",
        "abutment", "mast",   "stand", "occluder", "vegetation", "wall"};
    return names[static_cast<int>(s)];
}

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
    // Target supports (moved with a knocked target) and the box bounding target and supports.
    for (std::size_t i = 0; i < s.targets.size(); ++i) {
        const Target& t = s.targets[i];
        TargetGeometry g;
        g.supports = target_supports(t, target_centres[i], target_normals[i]);
        g.support_surface = t.mount == Target::Mount::stand ? Surface::stand : Surface::mast;
        const double half = t.kind == Target::Kind::sphere ? t.radius : 0.5 * t.size;
        g.lo = target_centres[i] - Eigen::Vector3d::Constant(half);
        g.hi = target_centres[i] + Eigen::Vector3d::Constant(half);
        for (const Cylinder& cyl : g.supports) {
            const Eigen::Vector3d r = Eigen::Vector3d::Constant(cyl.radius);
            g.lo = g.lo.cwiseMin(cyl.a - r).cwiseMin(cyl.b - r);
            g.hi = g.hi.cwiseMax(cyl.a + r).cwiseMax(cyl.b + r);
        }
        g.bound_centre = 0.5 * (g.lo + g.hi);
        g.bound_radius = 0.5 * (g.hi - g.lo).norm();
        target_geometry.push_back(std::move(g));
    }
    for (const Block& b : s.terrain.blocks) block_poses.push_back(b.pose(e));
    creep = s.terrain.creep.displacement(e);
    occluders = occluder_states(s, e);
    vegetation = vegetation_states(s, e);
    // A bound on |u| at this epoch ((z/H)^p <= 1), plus 1 mm.
    if (s.deformation.enabled) pier_reach += c.bending.top.norm();
    if (s.events.step_epoch >= 0 && e >= s.events.step_epoch) {
        pier_reach += s.events.step_displacement.norm();
    }
    const Pier& pier = s.pier;
    pier_reach += pier_tilt(s, e).norm() *
                  std::max(pier.height, std::hypot(pier.x1 - pier.x0, pier.y1 - pier.y0));
}

Hit cast_ray(const SceneAtEpoch& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
             double max_range) {
    const Site& site = *scene.site;
    Hit best;
    best.range = max_range;

    // Terrain: the valley profile (terrain.hpp), then the stable blocks on it.
    {
        Eigen::Vector3d n, p;
        const double t = intersect_terrain(site.terrain, o, d, best.range, n, scene.creep, &p);
        if (t < best.range) {
            consider(best, {Surface::ground, t, n,
                            terrain_albedo(site.texture, site.terrain, p.x(), p.y()), -1});
        }
    }
    for (std::size_t i = 0; i < site.terrain.blocks.size(); ++i) {
        const Block& k = site.terrain.blocks[i];
        // In the block's own frame (its yaw and its motion at this epoch undone).
        const Eigen::Isometry3d& P = scene.block_poses[i];
        const Eigen::Vector3d half = 0.5 * (k.hi - k.lo);
        const Eigen::Vector3d ol = P.linear().transpose() * (o - P.translation());
        const Eigen::Vector3d dl = P.linear().transpose() * d;
        const BoxHit bh = intersect_box(-half, half, ol, dl);
        if (bh.axis < 0 || bh.t >= best.range) continue;
        Eigen::Vector3d nl = Eigen::Vector3d::Zero();
        nl[bh.axis] = bh.low ? -1.0 : 1.0;
        const Eigen::Vector3d n = P.linear() * nl;
        const int face = pier_face(bh);
        // The texture is the block's own: it moves with it.
        const Eigen::Vector2d uv = face_uv(face, ol + bh.t * dl + k.centre());
        // Concrete texture at the block's own mean reflectance, independent pattern per block.
        const double scale = site.texture.albedo > 0.0 ? k.albedo / site.texture.albedo : 0.0;
        const double albedo =
            std::clamp(scale * concrete_albedo(site.texture, 20 + 5 * static_cast<int>(i) + face,
                                               uv.x(), uv.y()),
                       0.02, 1.0);
        const Surface surface = k.kind == Block::Kind::abutment ? Surface::abutment
                                : k.kind == Block::Kind::wall   ? Surface::wall
                                                                : Surface::foundation;
        Hit h{surface, bh.t, n, albedo, -1};
        h.part = static_cast<int>(i);
        consider(best, h);
    }

    // Pier: each face is its displaced surface {q + u(q) : q on the face}; the nearest
    // front-facing intersection whose material point lies on the face is the hit (see header).
    const Pier& pier = site.pier;
    const Eigen::Vector3d lo(pier.x0, pier.y0, 0.0), hi(pier.x1, pier.y1, pier.height);
    const Eigen::Vector3d reach = Eigen::Vector3d::Constant(scene.pier_reach);
    if (pier.round() && intersect_box(lo - reach, hi + reach, o, d).axis >= 0) {
        consider(best, cast_round_pier(scene, o, d));
    } else if (intersect_box(lo - reach, hi + reach, o, d).axis >= 0) {
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

    // Targets and their supports, each behind its bounding box.
    for (std::size_t i = 0; i < site.targets.size(); ++i) {
        const Target& tg = site.targets[i];
        const Eigen::Vector3d& c = scene.target_centres[i];
        const TargetGeometry& g = scene.target_geometry[i];
        if (!near_ray(g.bound_centre, g.bound_radius, o, d, best.range)) continue;
        double t_in, t_out;
        if (!box_interval(g.lo, g.hi, o, d, best.range, t_in, t_out)) continue;
        for (const Cylinder& cyl : g.supports) {
            Eigen::Vector3d n;
            const double t = intersect_cylinder(cyl.a, cyl.b, cyl.radius, o, d, n);
            if (t < best.range) {
                consider(best, {g.support_surface, t, n, kMastAlbedo, static_cast<int>(i)});
            }
        }
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
    // Occluders and vegetation.
    const Occlusion& occ = site.occlusion;
    for (std::size_t i = 0; i < occ.occluders.size(); ++i) {
        if (!scene.occluders[i].present) continue;
        const SolidHit sh =
            intersect_occluder(occ.occluders[i], scene.occluders[i], o, d, best.range);
        if (sh.t >= best.range) continue;
        Hit h{Surface::occluder, sh.t, sh.normal, occ.occluders[i].albedo, -1};
        h.part = static_cast<int>(i);
        consider(best, h);
    }
    for (std::size_t i = 0; i < occ.vegetation.size(); ++i) {
        const SolidHit sh =
            intersect_vegetation(occ.vegetation[i], scene.vegetation[i], o, d, best.range);
        if (sh.t >= best.range) continue;
        Hit h{Surface::vegetation, sh.t, sh.normal, occ.vegetation[i].albedo, -1};
        h.part = static_cast<int>(i);
        consider(best, h);
    }
    if (best.surface == Surface::none) best.range = std::numeric_limits<double>::infinity();
    return best;
}

}  // namespace tlsmon::sim
