#include "algorithms/primitives/primitive.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tlsmon::primitives {

namespace {

// (a + θ1·b1 + θ2·b2) and its length.
Eigen::Vector3d leaned(const Frame& f, double t1, double t2, double& length) {
    const Eigen::Vector3d v = f.a + t1 * f.b1 + t2 * f.b2;
    length = v.norm();
    return v / length;
}

}  // namespace

const char* to_string(Kind kind) {
    switch (kind) {
        case Kind::plane:
            return "plane";
        case Kind::cylinder:
            return "cylinder";
        case Kind::sphere:
            return "sphere";
    }
    return "?";
}

Kind kind_from_string(const std::string& name) {
    for (const Kind k : {Kind::plane, Kind::cylinder, Kind::sphere})
        if (name == to_string(k)) return k;
    throw Error("unknown primitive '" + name + "' (expected plane, cylinder or sphere)");
}

int parameter_count(Kind kind) {
    return kind == Kind::plane ? 3 : kind == Kind::cylinder ? 5 : 4;
}

Frame Frame::about(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
    Frame f;
    f.origin = origin;
    f.a = direction.normalized();
    const Eigen::Vector3d e =
        std::abs(f.a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    f.b1 = (e - f.a * f.a.dot(e)).normalized();
    f.b2 = f.a.cross(f.b1);
    return f;
}

Eigen::Vector3d Primitive::direction() const {
    double length = 1.0;
    switch (kind) {
        case Kind::plane:
            return leaned(frame, x[0], x[1], length);
        case Kind::cylinder:
            return leaned(frame, x[2], x[3], length);
        case Kind::sphere:
            break;
    }
    return frame.a;
}

Eigen::Vector3d Primitive::point() const {
    switch (kind) {
        case Kind::plane:
            return frame.origin + x[2] * direction();
        case Kind::cylinder:
            return frame.origin + x[0] * frame.b1 + x[1] * frame.b2;
        case Kind::sphere:
            break;
    }
    return frame.origin + x.head<3>();
}

double Primitive::radius() const {
    return kind == Kind::cylinder ? x[4] : kind == Kind::sphere ? x[3] : 0.0;
}

double Primitive::distance(const Eigen::Vector3d& p, Eigen::Ref<Eigen::VectorXd> g) const {
    const Frame& f = frame;
    switch (kind) {
        case Kind::plane: {
            // d = n·(p − c) − δ;  ∂n/∂θk = (bk − n(n·bk))/L.
            double L = 1.0;
            const Eigen::Vector3d n = leaned(f, x[0], x[1], L);
            const Eigen::Vector3d v = p - f.origin;
            g[0] = v.dot(f.b1 - n * n.dot(f.b1)) / L;
            g[1] = v.dot(f.b2 - n * n.dot(f.b2)) / L;
            g[2] = -1.0;
            return n.dot(v) - x[2];
        }
        case Kind::cylinder: {
            // d = ‖ρ‖ − r, ρ = v − (v·A)A, v = p − P: ∂d/∂P = −ρ̂, ∂d/∂A = −h·ρ̂ (h = v·A),
            // and ρ̂ ⟂ A, so ∂d/∂θk = −h·(ρ̂·bk)/L.
            double L = 1.0;
            const Eigen::Vector3d A = leaned(f, x[2], x[3], L);
            const Eigen::Vector3d v = p - point();
            const double h = v.dot(A);
            const Eigen::Vector3d rho = v - h * A;
            const double len = rho.norm();
            const Eigen::Vector3d u = len > 0.0 ? Eigen::Vector3d(rho / len) : f.b1;
            g[0] = -u.dot(f.b1);
            g[1] = -u.dot(f.b2);
            g[2] = h * g[0] / L;
            g[3] = h * g[1] / L;
            g[4] = -1.0;
            return len - x[4];
        }
        case Kind::sphere: {
            const Eigen::Vector3d v = p - point();
            const double len = v.norm();
            const Eigen::Vector3d u = len > 0.0 ? Eigen::Vector3d(v / len) : f.a;
            g.head<3>() = -u;
            g[3] = -1.0;
            return len - x[3];
        }
    }
    return 0.0;
}

Eigen::Vector3d Primitive::normal_at(const Eigen::Vector3d& p) const {
    if (kind == Kind::plane) return direction();
    Eigen::Vector3d v = p - point();
    if (kind == Kind::cylinder) {
        const Eigen::Vector3d A = direction();
        v -= v.dot(A) * A;
    }
    const double len = v.norm();
    return len > 0.0 ? Eigen::Vector3d(v / len) : frame.a;
}

Primitive plane_through(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
    Primitive p;
    p.kind = Kind::plane;
    p.frame = Frame::about(point, normal);
    p.x = Eigen::VectorXd::Zero(3);
    return p;
}

Primitive cylinder_about(const Eigen::Vector3d& axis_point, const Eigen::Vector3d& axis,
                         double radius) {
    // The axis points up (level: towards +x, then +y), whichever way a fit found it.
    Eigen::Vector3d up = axis;
    for (int i : {2, 0, 1}) {
        if (std::abs(up[i]) > 1e-9) {
            if (up[i] < 0) up = -up;
            break;
        }
    }
    Primitive p;
    p.kind = Kind::cylinder;
    p.frame = Frame::about(axis_point, up);
    p.x = Eigen::VectorXd::Zero(5);
    p.x[4] = radius;
    return p;
}

Primitive sphere_at(const Eigen::Vector3d& centre, double radius) {
    Primitive p;
    p.kind = Kind::sphere;
    p.frame = Frame::about(centre, Eigen::Vector3d::UnitZ());
    p.x = Eigen::VectorXd::Zero(4);
    p.x[3] = radius;
    return p;
}

}  // namespace tlsmon::primitives
