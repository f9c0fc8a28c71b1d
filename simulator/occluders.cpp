#include "simulator/occluders.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "simulator/random.hpp"
#include "simulator/terrain.hpp"

namespace tlsmon::sim {

namespace {

constexpr std::uint64_t kOccluderStream = 0x6f63636c756465ULL;
constexpr std::uint64_t kVegetationStream = 0x7665676574ULL;

// Three values in [−1, 1] from one 64-bit hash (21 bits each).
Eigen::Vector3d unit_cube(std::uint64_t h) {
    constexpr double scale = 2.0 / static_cast<double>((1u << 21) - 1);
    return {static_cast<double>(h & 0x1fffff) * scale - 1.0,
            static_cast<double>((h >> 21) & 0x1fffff) * scale - 1.0,
            static_cast<double>((h >> 42) & 0x1fffff) * scale - 1.0};
}

double unit(std::uint64_t h) {
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

std::uint64_t voxel_hash(std::uint64_t seed, int i, int j, int k) {
    return hash_combine(hash_combine(hash_combine(seed, static_cast<std::uint64_t>(i)),
                                     static_cast<std::uint64_t>(j)),
                        static_cast<std::uint64_t>(k));
}

}  // namespace

std::vector<OccluderState> occluder_states(const Site& site, int epoch) {
    std::vector<OccluderState> out;
    const Occlusion& occ = site.occlusion;
    for (std::size_t i = 0; i < occ.occluders.size(); ++i) {
        const Occluder& o = occ.occluders[i];
        Rng rng(hash_combine(hash_combine(hash_combine(occ.seed, kOccluderStream),
                                          static_cast<std::uint64_t>(epoch)),
                             i));
        OccluderState s;
        const double draw = rng.uniform(), where = rng.uniform(), way = rng.uniform();
        s.present = draw < o.probability;
        const Eigen::Vector2d xy = o.path_start + where * (o.path_end - o.path_start);
        const Eigen::Vector2d along = o.path_end - o.path_start;
        s.heading = std::atan2(along.y(), along.x()) + (way < 0.5 ? 0.0 : 3.141592653589793);
        // Stands on the ground; sunk 0.2 m so that no gap opens under it on a slope.
        s.base = {xy.x(), xy.y(), terrain_height(site.terrain, xy.y()) - 0.2};
        const double reach = 0.5 * std::hypot(o.length, o.width);
        s.lo = s.base - Eigen::Vector3d(reach, reach, 0.0);
        s.hi = s.base + Eigen::Vector3d(reach, reach, o.height + 0.2);
        out.push_back(s);
    }
    return out;
}

std::vector<VegetationState> vegetation_states(const Site& site, int epoch) {
    std::vector<VegetationState> out;
    const Occlusion& occ = site.occlusion;
    for (std::size_t i = 0; i < occ.vegetation.size(); ++i) {
        const Vegetation& v = occ.vegetation[i];
        VegetationState s;
        s.ground_z = terrain_height(site.terrain, v.centre.y());
        // The crown's centre 0.6 of its half-height above the ground: a bush on the ground.
        s.centre = {v.centre.x(), v.centre.y(), s.ground_z + 0.6 * v.radii.z()};
        for (int a = 0; a < 3; ++a) {
            s.cells[a] = static_cast<int>(std::ceil(2.0 * v.radii[a] / v.leaf_spacing));
        }
        s.lo = s.centre - 0.5 * v.leaf_spacing * s.cells.cast<double>();
        s.hi = s.centre + 0.5 * v.leaf_spacing * s.cells.cast<double>();
        s.seed = hash_combine(hash_combine(occ.seed, kVegetationStream), i);
        s.epoch_seed = hash_combine(s.seed, static_cast<std::uint64_t>(epoch) + 1);
        out.push_back(s);
    }
    return out;
}

SolidHit intersect_occluder(const Occluder& o, const OccluderState& s,
                            const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double t_max) {
    SolidHit hit;
    if (!s.present) return hit;
    double t_in, t_out;
    if (!box_interval(s.lo, s.hi, origin, d, t_max, t_in, t_out)) return hit;
    if (o.kind == Occluder::Kind::person) {
        Eigen::Vector3d n;
        const double t = intersect_cylinder(s.base, s.base + Eigen::Vector3d(0, 0, o.height + 0.2),
                                            0.5 * o.width, origin, d, n);
        if (t < t_max) hit = {t, n};
        return hit;
    }
    // A vehicle: a box in its own frame (x along the heading), ray turned into it.
    const double c = std::cos(s.heading), sn = std::sin(s.heading);
    const auto to_local = [&](const Eigen::Vector3d& v) {
        return Eigen::Vector3d(c * v.x() + sn * v.y(), -sn * v.x() + c * v.y(), v.z());
    };
    const Eigen::Vector3d lo(-0.5 * o.length, -0.5 * o.width, 0.0);
    const Eigen::Vector3d hi(0.5 * o.length, 0.5 * o.width, o.height + 0.2);
    const BoxHit b = intersect_box(lo, hi, to_local(origin - s.base), to_local(d));
    if (b.axis < 0 || b.t >= t_max) return hit;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[b.axis] = b.low ? -1.0 : 1.0;
    hit.t = b.t;
    hit.normal = {c * n.x() - sn * n.y(), sn * n.x() + c * n.y(), n.z()};
    return hit;
}

SolidHit intersect_vegetation(const Vegetation& v, const VegetationState& s,
                              const Eigen::Vector3d& origin, const Eigen::Vector3d& d,
                              double t_max) {
    SolidHit hit;
    double t_in, t_out;
    if (!box_interval(s.lo, s.hi, origin, d, t_max, t_in, t_out)) return hit;
    const double h = v.leaf_spacing;
    const double fixed_reach = 0.5 * h - v.leaf_radius - v.sway;
    // Voxel walk (Amanatides & Woo 1987): the voxel of the entry point, then always into
    // the neighbour whose boundary the ray crosses first.
    const Eigen::Vector3d p = origin + t_in * d - s.lo;
    Eigen::Vector3i cell, step;
    Eigen::Vector3d t_next, t_delta;
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(static_cast<int>(std::floor(p[a] / h)), 0, s.cells[a] - 1);
        if (d[a] > 1e-15) {
            step[a] = 1;
            t_delta[a] = h / d[a];
            t_next[a] = t_in + ((cell[a] + 1) * h - p[a]) / d[a];
        } else if (d[a] < -1e-15) {
            step[a] = -1;
            t_delta[a] = -h / d[a];
            t_next[a] = t_in + (cell[a] * h - p[a]) / d[a];
        } else {
            step[a] = 0;
            t_delta[a] = t_next[a] = kNoHit;
        }
    }
    const Eigen::Vector3d inv_r2 = v.radii.cwiseProduct(v.radii).cwiseInverse();
    while (true) {
        const Eigen::Vector3d centre =
            s.lo + (cell.cast<double>() + Eigen::Vector3d::Constant(0.5)) * h;
        const Eigen::Vector3d e = centre - s.centre;
        if (e.cwiseProduct(e).dot(inv_r2) <= 1.0 && centre.z() - v.leaf_radius > s.ground_z) {
            const std::uint64_t vh = voxel_hash(s.seed, cell.x(), cell.y(), cell.z());
            if (unit(vh) < v.density) {
                const Eigen::Vector3d leaf =
                    centre + fixed_reach * unit_cube(mix64(vh)) +
                    v.sway * unit_cube(voxel_hash(s.epoch_seed, cell.x(), cell.y(), cell.z()));
                const double t = intersect_sphere(leaf, v.leaf_radius, origin, d);
                if (t < t_max) {
                    hit.t = t;
                    hit.normal = (origin + t * d - leaf) / v.leaf_radius;
                    return hit;
                }
            }
        }
        int a = 0;
        if (t_next[1] < t_next[a]) a = 1;
        if (t_next[2] < t_next[a]) a = 2;
        if (t_next[a] > t_out) return hit;
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= s.cells[a]) return hit;
        t_next[a] += t_delta[a];
    }
}

void validate_occlusion(const Occlusion& occ) {
    for (const Vegetation& v : occ.vegetation) {
        if (v.leaf_radius + v.sway > 0.5 * v.leaf_spacing) {
            throw Error("vegetation '" + v.name +
                        "': leaf_radius + sway must not exceed half the leaf_spacing");
        }
    }
}

const char* occluder_kind_name(Occluder::Kind k) {
    return k == Occluder::Kind::vehicle ? "vehicle" : "person";
}

}  // namespace tlsmon::sim
