#include "simulator/scene_truth.hpp"

#include <cmath>
#include <numbers>

#include "simulator/occluders.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/target_layout.hpp"

namespace tlsmon::sim {

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}

}  // namespace

TargetSightlines target_sightlines(const SceneAtEpoch& scene, std::size_t i) {
    const Site& site = *scene.site;
    const Target& t = site.targets.at(i);
    const Eigen::Vector3d o = site.scanner.position;
    const Eigen::Vector3d c = scene.target_centres[i];
    const Eigen::Vector3d view = (c - o).normalized();
    // Two directions across the line of sight (sphere) or in the board's plane.
    Eigen::Vector3d u, v;
    double reach;
    if (t.kind == Target::Kind::sphere) {
        u = view.cross(Eigen::Vector3d::UnitZ()).normalized();
        v = u.cross(view).normalized();
        reach = 0.7 * t.radius;
    } else {
        const Eigen::Vector3d& n = scene.target_normals[i];
        u = Eigen::Vector3d(-n.y(), n.x(), 0.0);
        v = Eigen::Vector3d::UnitZ();
        reach = 0.35 * t.size;
    }
    TargetSightlines s;
    for (int k = 0; k < 9; ++k) {
        Eigen::Vector3d p = c;
        if (k > 0) {
            const double a = (k - 1) * std::numbers::pi / 4.0;
            // Board: the square's ring (corners at 45°), sphere: a circle.
            const double scale = t.kind == Target::Kind::sphere
                                     ? 1.0
                                     : 1.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a)));
            p += reach * scale * (std::cos(a) * u + std::sin(a) * v);
        }
        const Eigen::Vector3d d = (p - o).normalized();
        const Hit h = cast_ray(scene, o, d, site.scanner.max_range);
        ++s.rays;
        if ((h.surface == Surface::sphere || h.surface == Surface::checkerboard) &&
            h.target == static_cast<int>(i)) {
            ++s.reach;
        } else if (h.surface == Surface::occluder || h.surface == Surface::vegetation) {
            ++s.occluded;
        }
    }
    return s;
}

void add_scene_truth(nlohmann::json& j, const Site& site, int epoch, double hours,
                     const RenderedScan* rendered) {
    using nlohmann::json;
    const Terrain& tr = site.terrain;
    json blocks = json::array();
    for (const Block& b : tr.blocks) {
        // Its motion at this epoch (identity before motion.from_epoch): which planar surface
        // moved and by how much, to score the congruence test (docs/simulator.md).
        const Eigen::Isometry3d m = b.displacement(epoch);
        const Eigen::AngleAxisd rotation(m.linear());
        const Eigen::Vector3d c = b.centre();
        blocks.push_back(
            {{"name", b.name},
             {"kind", kind_name(b.kind)},
             {"lo", vec(b.lo)},
             {"hi", vec(b.hi)},
             {"yaw_deg", b.yaw_deg},
             {"albedo", b.albedo},
             {"moved", b.motion.from_epoch >= 0 && epoch >= b.motion.from_epoch},
             {"centre_displacement_m", vec(Eigen::Vector3d(m * c - c))},
             {"rotation_arcsec", rotation.angle() * 180.0 * 3600.0 / 3.141592653589793},
             {"rotation_axis", vec(rotation.axis())}});
    }
    j["terrain"] = {{"model", "z = h(y), piecewise linear through the profile, level beyond it"},
                    {"profile_y", tr.profile_y},
                    {"profile_z", tr.profile_z},
                    {"albedo", tr.albedo},
                    {"blocks", blocks}};
    if (tr.creep.from_epoch >= 0) {
        // The creeping patch and how far it has moved by this epoch (every point alike).
        j["terrain"]["creep"] = {{"from_epoch", tr.creep.from_epoch},
                                 {"centre", {tr.creep.centre.x(), tr.creep.centre.y()}},
                                 {"radius", tr.creep.radius},
                                 {"rate_m", vec(tr.creep.rate)},
                                 {"displacement_m", vec(tr.creep.displacement(epoch))}};
    }

    const SceneAtEpoch scene(site, epoch, hours);
    json sight = json::array();
    for (std::size_t i = 0; i < site.targets.size() && i < j["targets"].size(); ++i) {
        const Target& t = site.targets[i];
        json& tj = j["targets"][i];
        tj["mount"] = mount_name(t.mount);
        tj["base_z"] = t.base_z;
        json parts = json::array();
        for (const Cylinder& c : scene.target_geometry[i].supports) {
            parts.push_back({{"from", vec(c.a)}, {"to", vec(c.b)}, {"radius", c.radius}});
        }
        tj["supports"] = parts;
        const TargetSightlines s = target_sightlines(scene, i);
        const double occluded = static_cast<double>(s.occluded) / s.rays;
        tj["sightlines"] = {{"rays", s.rays}, {"reach_target", s.reach}, {"occluded", s.occluded}};
        tj["occluded"] = s.occluded > 0;
        sight.push_back(
            {{"target", t.name}, {"occluded_fraction", occluded}, {"occluded", s.occluded > 0}});
    }

    const Occlusion& occ = site.occlusion;
    json occluders = json::array();
    for (std::size_t i = 0; i < occ.occluders.size(); ++i) {
        const Occluder& o = occ.occluders[i];
        const OccluderState& st = scene.occluders[i];
        json oj = {{"name", o.name},        {"kind", occluder_kind_name(o.kind)},
                   {"present", st.present}, {"probability", o.probability},
                   {"length", o.length},    {"width", o.width},
                   {"height", o.height}};
        if (st.present) {
            oj["position"] = vec(st.base + Eigen::Vector3d(0.0, 0.0, 0.2));
            oj["heading_deg"] = st.heading * 180.0 / std::numbers::pi;
        }
        occluders.push_back(oj);
    }
    json vegetation = json::array();
    for (std::size_t i = 0; i < occ.vegetation.size(); ++i) {
        const Vegetation& v = occ.vegetation[i];
        vegetation.push_back({{"name", v.name},
                              {"centre", vec(scene.vegetation[i].centre)},
                              {"radii", vec(v.radii)},
                              {"leaf_spacing", v.leaf_spacing},
                              {"leaf_radius", v.leaf_radius},
                              {"density", v.density},
                              {"sway", v.sway}});
    }
    j["occlusion"] = {{"seed", occ.seed},
                      {"occluders", occluders},
                      {"vegetation", vegetation},
                      {"targets", sight}};

    if (rendered) {
        json counts = json::object();
        for (int k = 1; k < kSurfaceKinds; ++k) {
            counts[surface_name(static_cast<Surface>(k))] = rendered->points_by_surface[k];
        }
        j["scan"]["points_by_surface"] = counts;
    }
}

}  // namespace tlsmon::sim
