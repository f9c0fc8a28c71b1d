#pragma once
// Ray casting against the simulated scene at one epoch: ground plane, pier (deformed),
// optional deck, sphere and checkerboard targets.
//
// How the deformed pier stays geometrically consistent: the ray is first cast against the
// undeformed box, giving a material point q on face f (normal n). The deformed face near q
// is the plane through q + u(q) with normal n (the field bends the face by at most a few
// centimetres over tens of metres, so the change of the normal, ~1e-6 rad, is neglected).
// The ray is intersected with that plane, giving x; the material point seen there is
// q = x − u(q), which lies on the undeformed face again. Two more passes converge to
// micrometres because u varies slowly along the face. The range is |x − origin| along the
// ray, and the reflectance is taken at the material point q, so the texture moves with the
// surface exactly as the field says (what keypoint tracking measures). Rays within a few
// centimetres of a face edge may see the undeformed silhouette; that edge band is ignored.
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

enum class Surface { none, ground, pier, deck, sphere, checkerboard };

struct Hit {
    Surface surface = Surface::none;
    double range = std::numeric_limits<double>::infinity();  // along the unit ray
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();        // outward, unit
    double albedo = 0.0;                                     // reflectance at the hit
    int target = -1;                                         // index for target hits
};

// Faces of the pier box: 0 west (x0), 1 east (x1), 2 south (y0), 3 north (y1), 4 top.
struct SceneAtEpoch {
    const Site* site = nullptr;
    int epoch = 0;
    double hours = 0.0;
    std::vector<Eigen::Vector3d> target_centres;  // true centres at this epoch
    std::vector<Eigen::Vector3d> target_normals;  // checkerboards: facing the scanner

    SceneAtEpoch(const Site& s, int epoch, double hours);
};

// Nearest hit of the ray origin + t·dir (dir unit) with t in (0, max_range].
Hit cast_ray(const SceneAtEpoch& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
             double max_range);

}  // namespace tlsmon::sim
