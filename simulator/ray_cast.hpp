#pragma once
// Ray casting against the simulated scene at one epoch: the terrain and its stable blocks,
// pier (deformed), optional deck, sphere and checkerboard targets with their masts and
// stands, occluders and vegetation. Every object but the terrain and the pier's faces is
// tested against its bounding box first.
//
// How the deformed pier stays geometrically consistent: each face f (normal n) of the box
// becomes the surface {q + u(q) : q on f}. Starting from the ray's hit q on the undeformed
// face plane, the deformed face near q is the plane through q + u(q) with normal n (the
// bent face tilts by at most D·p/H, 2e-3 rad at the top of the default pier; the fixed
// point below is exact regardless, and only the incidence angle for the intensity uses
// the undeformed normal, ≈ 2 % off at the top of the grazing wall at the peak). The ray is
// intersected with that plane, giving x; the material point seen there is q = x − u(q), which lies
// on the undeformed face plane again. The passes repeat until the range changes by less than 1 nm
// (a fixed point is exactly x = q + u(q)); u varies slowly, so two or three passes suffice. The hit
// counts only if q lies within the face: on the grazing west wall a shift δ along n moves the hit
// by δ / |cos incidence| (≈ 0.5 m for 20 mm at 87°) along the ray, so a ray cast against the
// undeformed box alone would see wall beyond the displaced edges and miss the band the top
// edge moved into. The nearest front-facing face wins. The range is |x − origin| along the
// ray, and the reflectance is taken at the material point q, so the texture moves with the
// surface exactly as the field says (what keypoint tracking measures).
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "simulator/deformation.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/occluders.hpp"
#include "simulator/scene.hpp"
#include "simulator/target_layout.hpp"

namespace tlsmon::sim {

enum class Surface {
    none,
    ground,
    pier,
    deck,
    sphere,
    checkerboard,
    // Terrain, stable blocks, target supports and occluders.
    foundation,
    abutment,
    mast,
    stand,
    occluder,
    vegetation,
    wall  // retaining walls and building faces (Block::Kind::wall)
};
constexpr int kSurfaceKinds = 13;
// "ground", "pier", ... as in the truth's `points_by_surface`.
const char* surface_name(Surface s);

struct Hit {
    Surface surface = Surface::none;
    double range = std::numeric_limits<double>::infinity();  // along the unit ray
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();        // outward, unit
    double albedo = 0.0;                                     // reflectance at the hit
    int target = -1;                                         // index for target hits
    int face = -1;  // pier faces 0–4, deck faces 5–9 (see below); -1 otherwise
    // Surface coordinates of the hit, m: on pier and deck faces the material point's (u, v)
    // of concrete_albedo; on a checkerboard (across, up) from its centre; else zero.
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    int part = -1;  // block, occluder or vegetation patch index; -1 otherwise
};

// A target with its supports at one epoch, and the box bounding them all.
struct TargetGeometry {
    std::vector<Cylinder> supports;
    Surface support_surface = Surface::mast;
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    Eigen::Vector3d bound_centre = Eigen::Vector3d::Zero();  // sphere around the box
    double bound_radius = 0.0;
};

// Faces of the pier box: 0 west (x0), 1 east (x1), 2 south (y0), 3 north (y1), 4 top.
struct SceneAtEpoch {
    const Site* site = nullptr;
    int epoch = 0;
    double hours = 0.0;
    std::vector<Eigen::Vector3d> target_centres;      // true centres at this epoch
    std::vector<Eigen::Vector3d> target_normals;      // checkerboards: facing the scanner
    double pier_reach = 0.001;                        // m, bound on |u| at this epoch
    PierDisplacementField displacement;               // u(q) at this epoch
    std::vector<TargetGeometry> target_geometry;      // supports and bounds, per target
    std::vector<OccluderState> occluders;             // where each occluder is at this epoch
    std::vector<VegetationState> vegetation;          // leaves at this epoch
    std::vector<Eigen::Isometry3d> block_poses;       // each block's own frame into the site's
    Eigen::Vector3d creep = Eigen::Vector3d::Zero();  // the creeping ground's displacement

    SceneAtEpoch(const Site& s, const EpochConditions& conditions);
    // At kDefaultStartUtc + hours (epoch_conditions.hpp).
    SceneAtEpoch(const Site& s, int epoch, double hours);
};

// Nearest hit of the ray origin + t·dir (dir unit) with t in (0, max_range].
Hit cast_ray(const SceneAtEpoch& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
             double max_range);

}  // namespace tlsmon::sim
