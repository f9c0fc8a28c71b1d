#include "algorithms/registration/plane_registration.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/so3.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {

namespace {

using Jacobian = Eigen::Matrix<double, 3, 6>;

// The misclosure w, its covariance Σ_ww and its Jacobian J under (R, t) (header, eqs.).
struct Linearised {
    Eigen::Vector3d w;
    Eigen::Matrix3d covariance;
    Jacobian J;
};

Linearised linearise(const PlaneCorrespondence& p, const Eigen::Matrix3d& R,
                     const Eigen::Vector3d& t) {
    const FittedPlane& ref = p.reference;
    const Eigen::Vector3d& nr = ref.normal;
    Eigen::Vector3d ne = R * p.epoch.normal;
    if (ne.dot(nr) < 0.0) ne = -ne;  // the fits' signs are arbitrary
    // u: the reference's long axis made orthogonal to n_r (it is, up to rounding).
    const Eigen::Vector3d u = (ref.axis_long - ref.axis_long.dot(nr) * nr).normalized();
    const Eigen::Vector3d v = nr.cross(u);
    Eigen::Matrix<double, 3, 2> U;
    U << u, v;
    const Eigen::Vector3d ce = R * p.epoch.centroid;
    const Eigen::Vector3d a = ce + t - ref.centroid;

    Linearised l;
    l.w << u.dot(ne), v.dot(ne), nr.dot(a);
    const Eigen::Matrix3d tilt =
        ref.normal_covariance + R * p.epoch.normal_covariance * R.transpose();
    l.covariance.topLeftCorner<2, 2>() = U.transpose() * tilt * U;
    l.covariance.topRightCorner<2, 1>() = -U.transpose() * ref.normal_covariance * a;
    l.covariance.bottomLeftCorner<1, 2>() = l.covariance.topRightCorner<2, 1>().transpose();
    l.covariance(2, 2) =
        a.dot(ref.normal_covariance * a) + ref.centroid_variance + p.epoch.centroid_variance;
    l.J.setZero();
    l.J.topLeftCorner<2, 3>() = -U.transpose() * skew(ne);
    l.J.block<1, 3>(2, 0) = -nr.transpose() * skew(ce);
    l.J.block<1, 3>(2, 3) = nr.transpose();
    return l;
}

// The planes must fix every direction of the rotation and the translation: a direction in
// which the normal matrix leaves a σ above 0.001 rad (206″) or 0.1 m is one that no plane
// faces (every plane parallel to it), and the adjustment would wander along it.
void check_datum(const Eigen::Matrix<double, 6, 6>& N) {
    const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(N);
    if (!lu.isInvertible())
        throw Error("plane registration: singular normal matrix (the normals do not span space)");
    const Eigen::Matrix<double, 6, 6> Q = lu.inverse();
    const auto weakest = [&](int first) {
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Q.block<3, 3>(first, first));
        return std::pair{std::sqrt(std::max(0.0, es.eigenvalues()(2))),
                         Eigen::Vector3d(es.eigenvectors().col(2))};
    };
    const auto [rotation, axis] = weakest(0);
    const auto [translation, direction] = weakest(3);
    const auto text = [](const Eigen::Vector3d& v) {
        char b[64];
        std::snprintf(b, sizeof b, "(%.2f, %.2f, %.2f)", v.x(), v.y(), v.z());
        return std::string(b);
    };
    if (translation > 0.1)
        throw Error("plane registration: the planes do not fix the translation along " +
                    text(direction) + " (σ " + std::to_string(translation) +
                    " m): no plane in the datum faces that way");
    if (rotation > 0.001)
        throw Error("plane registration: the planes do not fix the rotation about " + text(axis) +
                    " (σ " + std::to_string(rotation) + " rad)");
}

double quadratic_form(const Eigen::Vector3d& w, const Eigen::Matrix3d& Q) {
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(Q);
    if (ldlt.info() != Eigen::Success) return 0.0;
    return w.dot(ldlt.solve(w));
}

}  // namespace

PlaneMisclosure plane_misclosure(const PlaneCorrespondence& planes, const Eigen::Matrix3d& R,
                                 const Eigen::Vector3d& t) {
    const Linearised l = linearise(planes, R, t);
    PlaneMisclosure m;
    m.w = l.w;
    m.covariance = m.cofactor = l.covariance;
    m.test_statistic = quadratic_form(l.w, l.covariance);
    return m;
}

PlaneAdjustment adjust_planes(std::span<const PlaneCorrespondence> planes,
                              const std::vector<bool>& use, const RigidTransform& start,
                              const RigidTransformParams& params) {
    const auto used = [&](std::size_t i) { return use.empty() || use[i]; };
    std::size_t n_used = 0;
    for (std::size_t i = 0; i < planes.size(); ++i) n_used += used(i);
    if (n_used < 3)
        throw Error("plane registration: " + std::to_string(n_used) + " planes, at least 3 needed");

    RigidTransform T = start;
    T.scale = 1.0;
    T.scale_estimated = false;
    T.residuals.clear();
    using Matrix6 = Eigen::Matrix<double, 6, 6>;
    using Vector6 = Eigen::Matrix<double, 6, 1>;
    Matrix6 N;
    Vector6 b;
    const auto assemble = [&] {
        N.setZero();
        b.setZero();
        for (std::size_t i = 0; i < planes.size(); ++i) {
            if (!used(i)) continue;
            const Linearised l = linearise(planes[i], T.rotation, T.translation);
            const Eigen::LLT<Eigen::Matrix3d> llt(l.covariance);
            if (llt.info() != Eigen::Success)
                throw Error("plane registration: the covariance of plane pair " +
                            std::to_string(i) + " is not positive definite");
            const Eigen::Matrix3d P = llt.solve(Eigen::Matrix3d::Identity());
            N.noalias() += l.J.transpose() * P * l.J;
            b.noalias() -= l.J.transpose() * P * l.w;  // δx = −N⁻¹·Jᵀ·P·w
        }
    };
    bool converged = false;
    for (int it = 0; it < params.max_iterations; ++it) {
        assemble();
        if (it == 0) check_datum(N);
        const Eigen::LDLT<Matrix6> ldlt(N);
        const Vector6 dx = ldlt.solve(b);
        if (ldlt.info() != Eigen::Success || !dx.allFinite())
            throw Error(
                "plane registration: singular normal matrix (the normals do not span space)");
        T.rotation = exp_so3(dx.head<3>()) * T.rotation;
        T.translation += dx.tail<3>();
        T.iterations = it + 1;
        if (dx.head<3>().norm() < 1e-13 && dx.tail<3>().norm() < 1e-10) {
            converged = true;
            break;
        }
    }
    if (!converged)
        throw Error("plane registration: adjustment did not converge in " +
                    std::to_string(params.max_iterations) + " iterations");
    assemble();
    const Eigen::FullPivLU<Matrix6> lu(N);
    if (!lu.isInvertible() || lu.rcond() < 1e-14)
        throw Error("plane registration: singular normal matrix (the normals do not span space)");
    const Matrix6 Qxx = lu.inverse();

    PlaneAdjustment out;
    out.planes.resize(planes.size());
    T.omega_sq = 0.0;
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const Linearised l = linearise(planes[i], T.rotation, T.translation);
        PlaneMisclosure& m = out.planes[i];
        m.w = l.w;
        m.covariance = l.covariance;
        m.in_adjustment = used(i);
        const Eigen::Matrix3d JQJ = l.J * Qxx * l.J.transpose();
        // Q_vv = Q_ll − J·Q_xx·Jᵀ (Niemeier 2008, eq. 4.2-34); a plane left out is predicted.
        m.cofactor = m.in_adjustment ? Eigen::Matrix3d(l.covariance - JQJ)
                                     : Eigen::Matrix3d(l.covariance + JQJ);
        m.test_statistic = quadratic_form(m.w, m.cofactor);
        if (m.in_adjustment) T.omega_sq += quadratic_form(m.w, l.covariance);
    }
    T.redundancy = static_cast<int>(3 * n_used) - 6;
    T.variance_factor = T.redundancy > 0 ? T.omega_sq / T.redundancy : 0.0;
    T.covariance_factor = covariance_factor(params.scaling, T.variance_factor, T.redundancy);
    T.small_rotation_covariance.setZero();
    T.small_rotation_covariance.topLeftCorner<6, 6>() = T.covariance_factor * Qxx;
    finish_parameters(T);
    out.transform = T;
    return out;
}

CongruenceResult congruence_test(std::span<const PlaneCorrespondence> planes,
                                 const RigidTransform& start, const CongruenceParams& params,
                                 const std::vector<bool>& candidate) {
    CongruenceResult out;
    std::vector<bool> use = candidate.empty() ? std::vector<bool>(planes.size(), true) : candidate;
    RigidTransform from = start;
    for (;;) {
        out.adjustment = adjust_planes(planes, use, from, params.adjustment);
        from = out.adjustment.transform;
        const RigidTransform& T = out.adjustment.transform;
        const double limit = chi_square_quantile(1.0 - params.alpha, T.redundancy);
        out.global_omega.push_back(T.omega_sq);
        out.global_limit.push_back(limit);
        if (T.omega_sq <= limit) {
            out.congruent = true;
            return out;
        }
        const std::size_t left = static_cast<std::size_t>(std::count(use.begin(), use.end(), true));
        if (left <= params.min_planes) {
            out.note = "the global test still fails with " + std::to_string(left) +
                       " planes left (at least " + std::to_string(params.min_planes) +
                       " must stay in the datum)";
            return out;
        }
        // The plane whose removal lowers Ω the most leaves the datum.
        std::size_t worst = planes.size();
        for (std::size_t i = 0; i < planes.size(); ++i) {
            if (!use[i]) continue;
            if (worst == planes.size() || out.adjustment.planes[i].test_statistic >
                                              out.adjustment.planes[worst].test_statistic)
                worst = i;
        }
        use[worst] = false;
        out.moved.push_back(worst);
    }
}

}  // namespace tlsmon::registration
