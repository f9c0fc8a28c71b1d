#include "algorithms/primitives/primitive_change.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "core/error.hpp"

namespace tlsmon::primitives {

namespace {

// θk of a direction d in the frame: the tangents of its lean, (d·bk)/(d·a); their change
// for a change δd of d at d.
Eigen::Vector2d lean_change(const Frame& f, const Eigen::Vector3d& d, const Eigen::Vector3d& dd) {
    const double da = d.dot(f.a);
    const Eigen::Vector2d db(d.dot(f.b1), d.dot(f.b2)), ddb(dd.dot(f.b1), dd.dot(f.b2));
    return (ddb * da - db * dd.dot(f.a)) / (da * da);
}

// The parameters' change for the motion δp = ω × (p − c) + τ + σ·(p − c).
Eigen::VectorXd change_for(const Primitive& prim, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& omega, const Eigen::Vector3d& tau, double sigma) {
    const Frame& f = prim.frame;
    const auto motion = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
        return omega.cross(p - c) + tau + sigma * (p - c);
    };
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(parameter_count(prim.kind));
    switch (prim.kind) {
        case Kind::plane: {
            const Eigen::Vector3d n = prim.direction();
            dx.head<2>() = lean_change(f, n, omega.cross(n));
            dx[2] = n.dot(motion(prim.point()));
            break;
        }
        case Kind::cylinder: {
            // The moved axis crosses the plane through the origin ⟂ a where its point P moved
            // by m, slid back along A: δs = bk·(m − A·(m·a)/(A·a)).
            const Eigen::Vector3d A = prim.direction();
            const Eigen::Vector3d m = motion(prim.point());
            const Eigen::Vector3d slid = m - A * (m.dot(f.a) / A.dot(f.a));
            dx[0] = slid.dot(f.b1);
            dx[1] = slid.dot(f.b2);
            dx.segment<2>(2) = lean_change(f, A, omega.cross(A));
            dx[4] = sigma * prim.radius();
            break;
        }
        case Kind::sphere:
            dx.head<3>() = motion(prim.point());
            dx[3] = sigma * prim.radius();
            break;
    }
    return dx;
}

}  // namespace

Eigen::MatrixXd motion_jacobian(const Primitive& prim, const Eigen::Vector3d& centre) {
    Eigen::MatrixXd J(parameter_count(prim.kind), 7);
    for (int j = 0; j < 7; ++j) {
        Eigen::Vector3d omega = Eigen::Vector3d::Zero(), tau = Eigen::Vector3d::Zero();
        double sigma = 0.0;
        if (j < 3)
            omega[j] = 1.0;
        else if (j < 6)
            tau[j - 3] = 1.0;
        else
            sigma = 1.0;
        J.col(j) = change_for(prim, centre, omega, tau, sigma);
    }
    return J;
}

VectorTest test_change(const Eigen::VectorXd& v, const Eigen::MatrixXd& covariance, double alpha) {
    if (v.size() != covariance.rows() || covariance.rows() != covariance.cols() || v.size() == 0)
        throw Error("primitive change test: a vector of " + std::to_string(v.size()) +
                    " with a covariance of " + std::to_string(covariance.rows()) + " x " +
                    std::to_string(covariance.cols()));
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(covariance);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all())
        throw Error("primitive change test: the covariance is not positive definite");
    VectorTest t;
    const auto k = static_cast<double>(v.size());
    t.magnitude = v.norm();
    t.statistic = v.dot(ldlt.solve(v));
    t.limit = registration::chi_square_quantile(1.0 - alpha, k);
    // The direction of v, or for v = 0 the least precise one (the largest LoD).
    Eigen::VectorXd dir;
    if (t.magnitude > 0.0) {
        dir = v / t.magnitude;
    } else {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(covariance);
        dir = eig.eigenvectors().col(v.size() - 1);
    }
    t.lod = std::sqrt(t.limit / dir.dot(ldlt.solve(dir)));
    t.significant = t.statistic > t.limit;
    return t;
}

Change parameter_change(const Primitive& reference, const Eigen::MatrixXd& reference_covariance,
                        const Primitive& epoch, const Eigen::MatrixXd& epoch_covariance,
                        const Eigen::Matrix<double, 7, 7>& registration_covariance,
                        const Eigen::Vector3d& registration_centre) {
    if (reference.kind != epoch.kind)
        throw Error(std::string("primitive change: a ") + to_string(reference.kind) +
                    " against a " + to_string(epoch.kind));
    Change c;
    c.delta = epoch.x - reference.x;
    const Eigen::MatrixXd J = motion_jacobian(epoch, registration_centre);
    c.covariance =
        reference_covariance + epoch_covariance + J * registration_covariance * J.transpose();
    return c;
}

}  // namespace tlsmon::primitives
