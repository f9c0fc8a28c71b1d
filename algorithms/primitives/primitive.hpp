#pragma once
// A geometric primitive — plane, cylinder or sphere — described by a few parameters about a
// frame fixed once, from the reference epoch's fit (docs/primitives.md). Every epoch's fit
// uses the same frame, so the parameters of two epochs are directly comparable and their
// difference is the deformation (the thesis on rigid patches in TLS point clouds, §5.2).
//
// The frame: an origin c, a direction a (the cylinder's axis, the plane's normal; unused by
// the sphere) and b1, b2 completing a right-handed orthonormal basis, b1 the project's x axis
// made perpendicular to a (y when a lies within 26° of x), b2 = a × b1; a cylinder's axis
// points up (or towards +x, +y when level), so for a standing column b1, b2 are east and
// north and θ1, θ2 its lean towards them. Parameters:
//   plane    (θ1, θ2, δ):          n = (a + θ1·b1 + θ2·b2)/‖·‖, the plane n·(x − c) = δ
//   cylinder (s1, s2, θ1, θ2, r):  axis through c + s1·b1 + s2·b2 along (a + θ1·b1 + θ2·b2)/‖·‖
//   sphere   (x, y, z, r):         centre c + (x, y, z)
// θ1, θ2 are the tangents of the lean of the axis or normal towards b1 and b2.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace tlsmon::primitives {

enum class Kind { plane, cylinder, sphere };

const char* to_string(Kind kind);
// "plane", "cylinder" or "sphere"; throws tlsmon::Error otherwise.
Kind kind_from_string(const std::string& name);
// The number of parameters: 3, 5, 4.
int parameter_count(Kind kind);

struct Frame {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d a = Eigen::Vector3d::UnitZ(), b1 = Eigen::Vector3d::UnitX(),
                    b2 = Eigen::Vector3d::UnitY();
    // b1: the project's x axis (y when |a·x| ≥ 0.9) made perpendicular to `direction`;
    // b2 = a × b1.
    static Frame about(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);
};

struct Primitive {
    Kind kind = Kind::plane;
    Frame frame;
    Eigen::VectorXd x;  // the parameters above

    // The unit axis (cylinder) or normal (plane).
    Eigen::Vector3d direction() const;
    // The cylinder's axis point in the plane through the origin ⟂ a; the sphere's centre;
    // the plane's point c + δ·n.
    Eigen::Vector3d point() const;
    double radius() const;  // cylinder, sphere; 0 for a plane

    // The signed orthogonal distance of p from the surface (outside/along n positive) and
    // its gradient with respect to the parameters (the design matrix's row).
    double distance(const Eigen::Vector3d& p, Eigen::Ref<Eigen::VectorXd> gradient) const;
    // The unit surface normal at (the foot of) p.
    Eigen::Vector3d normal_at(const Eigen::Vector3d& p) const;
};

// From a first estimate (e.g. RANSAC's): the frame at `origin` along `direction` with zero
// tilts, and the offset, axis point or centre and radius given.
Primitive plane_through(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
Primitive cylinder_about(const Eigen::Vector3d& axis_point, const Eigen::Vector3d& axis,
                         double radius);
Primitive sphere_at(const Eigen::Vector3d& centre, double radius);

}  // namespace tlsmon::primitives
