#include "algorithms/registration/rigid_transform.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/so3.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {
namespace {

// Scalar weight of a pair for the closed form: the inverse mean variance of the difference.
double scalar_weight(const CentreObservation& c) {
    const double var = (c.reference_covariance.trace() + c.epoch_covariance.trace()) / 3.0;
    return var > 0.0 ? 1.0 / var : 1.0;
}

// The Euler-angle Jacobian: a small rotation θ (R̂ = exp([θ]×)·R) equals the Euler
// increments through θ = M·(dω, dφ, dκ), M = [R_z·R_y·e_x | R_z·e_y | e_z], from
// R_z(κ)·R_y(φ)·R_x(ω) differentiated factor by factor (Förstner & Wrobel 2016, §8.1.3).
Eigen::Matrix3d euler_rate_matrix(double phi, double kappa) {
    const Eigen::Matrix3d Rz =
        Eigen::AngleAxisd(kappa, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Matrix3d Ry = Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitY()).toRotationMatrix();
    Eigen::Matrix3d M;
    M.col(0) = Rz * Ry * Eigen::Vector3d::UnitX();
    M.col(1) = Rz * Eigen::Vector3d::UnitY();
    M.col(2) = Eigen::Vector3d::UnitZ();
    return M;
}

}  // namespace

void finish_parameters(RigidTransform& T) {
    const Eigen::Vector3d e = euler_from_rotation(T.rotation);
    T.omega = e(0);
    T.phi = e(1);
    T.kappa = e(2);
    T.quaternion = Eigen::Quaterniond(T.rotation).normalized();
    if (T.quaternion.w() < 0) T.quaternion.coeffs() *= -1.0;  // one sign: w ≥ 0
    // Σ_euler = J·Σ_θ·Jᵀ, J = blockdiag(M⁻¹, I, 1).
    ParameterCovariance J = ParameterCovariance::Identity();
    J.topLeftCorner<3, 3>() = euler_rate_matrix(T.phi, T.kappa).inverse();
    T.covariance = J * T.small_rotation_covariance * J.transpose();
}

double t_expansion(int redundancy) {
    if (redundancy <= 0) return 1.0;
    const double ratio = student_t_quantile(0.975, redundancy) / normal_quantile(0.975);
    return ratio * ratio;
}

double covariance_factor(CovarianceScaling scaling, double variance_factor, int redundancy) {
    if (redundancy <= 0) return 1.0;
    const double estimated = variance_factor * t_expansion(redundancy);
    switch (scaling) {
        case CovarianceScaling::a_priori:
            return 1.0;
        case CovarianceScaling::a_posteriori:
            return estimated;
        case CovarianceScaling::larger_of:
            break;
    }
    // The a priori factor when the residuals are no larger than the model says.
    return variance_factor > 1.0 ? std::max(1.0, estimated) : 1.0;
}

Eigen::Matrix4d RigidTransform::matrix() const {
    Eigen::Matrix4d H = Eigen::Matrix4d::Identity();
    H.topLeftCorner<3, 3>() = scale * rotation;
    H.topRightCorner<3, 1>() = translation;
    return H;
}

Eigen::Matrix3d rotation_from_euler(double omega, double phi, double kappa) {
    return (Eigen::AngleAxisd(kappa, Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(omega, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

Eigen::Vector3d euler_from_rotation(const Eigen::Matrix3d& R) {
    // R(2,0) = −sin φ, R(2,1) = cos φ·sin ω, R(2,2) = cos φ·cos ω, R(1,0) = sin κ·cos φ,
    // R(0,0) = cos κ·cos φ.
    const double phi = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
    return {std::atan2(R(2, 1), R(2, 2)), phi, std::atan2(R(1, 0), R(0, 0))};
}

RigidTransform closed_form_transform(std::span<const CentreObservation> centres,
                                     bool estimate_scale) {
    if (centres.size() < 3)
        throw Error("rigid transformation: " + std::to_string(centres.size()) +
                    " target centres, at least 3 needed");
    // Umeyama 1991, eqs. 34–36 (weighted means and cross-covariance), 39–42 (R, c, t).
    double W = 0.0;
    Eigen::Vector3d mx = Eigen::Vector3d::Zero(), my = Eigen::Vector3d::Zero();
    for (const auto& c : centres) {
        const double w = scalar_weight(c);
        W += w;
        mx += w * c.epoch;
        my += w * c.reference;
    }
    mx /= W;
    my /= W;
    Eigen::Matrix3d Sxy = Eigen::Matrix3d::Zero();
    double var_x = 0.0;
    for (const auto& c : centres) {
        const double w = scalar_weight(c);
        Sxy += w * (c.reference - my) * (c.epoch - mx).transpose();
        var_x += w * (c.epoch - mx).squaredNorm();
    }
    Sxy /= W;
    var_x /= W;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(Sxy, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Vector3d D = svd.singularValues();
    if (!(D(1) > 1e-12 * D(0)))
        throw Error(
            "rigid transformation: the target centres lie on a line; rotation about it is "
            "undetermined");
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1.0;

    RigidTransform T;
    T.rotation = svd.matrixU() * S * svd.matrixV().transpose();
    T.scale = estimate_scale ? (D.asDiagonal() * S).trace() / var_x : 1.0;
    T.translation = my - T.scale * T.rotation * mx;
    T.scale_estimated = estimate_scale;
    finish_parameters(T);
    return T;
}

RigidTransform estimate_rigid_transform(std::span<const CentreObservation> centres,
                                        const RigidTransformParams& params) {
    RigidTransform T = closed_form_transform(centres, params.estimate_scale);
    const int u = params.estimate_scale ? 7 : 6;
    const std::size_t n = centres.size();

    // Gauss–Markov adjustment of the equivalent observations X_i with cofactor
    // Q_i = Σ_X,i + s²·R·Σ_x,i·Rᵀ: both centres are measured, and the condition
    // X − (s·R·x + t) = 0 is linear in them, so this is the Gauss–Helmert model solved in its
    // equivalent Gauss–Markov form (Niemeier 2008, §5.2; Förstner & Wrobel 2016, §4.8.2).
    // Linearised at (R, t, s): X_i − (s·R·x_i + t) = A_i·dx with
    //   A_i = [ −s·[R·x_i]× | I | R·x_i ],   dx = (θ, dt, ds),   R̂ = exp([θ]×)·R.
    Eigen::MatrixXd N(u, u);
    Eigen::VectorXd b(u);
    std::vector<Eigen::Matrix3d> P(n);
    std::vector<Eigen::Matrix<double, 3, 7>> A(n);
    auto assemble = [&]() {
        N.setZero();
        b.setZero();
        for (std::size_t i = 0; i < n; ++i) {
            const auto& c = centres[i];
            const Eigen::Vector3d y = T.rotation * c.epoch;
            const Eigen::Matrix3d Q = c.reference_covariance + T.scale * T.scale * T.rotation *
                                                                   c.epoch_covariance *
                                                                   T.rotation.transpose();
            const Eigen::LLT<Eigen::Matrix3d> llt(Q);
            if (llt.info() != Eigen::Success)
                throw Error("rigid transformation: covariance of target centre " +
                            std::to_string(i) + " is not positive definite");
            P[i] = llt.solve(Eigen::Matrix3d::Identity());
            A[i].setZero();
            A[i].leftCols<3>() = -T.scale * skew(y);
            A[i].block<3, 3>(0, 3).setIdentity();
            if (params.estimate_scale) A[i].col(6) = y;
            const auto Ai = A[i].leftCols(u);
            const Eigen::Vector3d l = c.reference - (T.scale * y + T.translation);
            N.noalias() += Ai.transpose() * P[i] * Ai;
            b.noalias() += Ai.transpose() * P[i] * l;
        }
    };

    bool converged = false;
    for (int it = 0; it < params.max_iterations; ++it) {
        assemble();
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(N);
        const Eigen::VectorXd dx = ldlt.solve(b);
        if (ldlt.info() != Eigen::Success || !dx.allFinite())
            throw Error("rigid transformation: singular normal matrix (target geometry too weak)");
        T.rotation = exp_so3(dx.head<3>()) * T.rotation;
        T.translation += dx.segment<3>(3);
        if (params.estimate_scale) T.scale += dx(6);
        T.iterations = it + 1;
        // 1e-13 rad is 15 nm at 150 m; 1e-10 m in translation.
        if (dx.head<3>().norm() < 1e-13 && dx.segment<3>(3).norm() < 1e-10 &&
            (!params.estimate_scale || std::fabs(dx(6)) < 1e-13)) {
            converged = true;
            break;
        }
    }
    if (!converged)
        throw Error("rigid transformation: adjustment did not converge in " +
                    std::to_string(params.max_iterations) + " iterations");
    // The normal matrix, weights and design at the solution.
    assemble();
    // Q_xx = N⁻¹ (Niemeier 2008, eq. 4.2-26); checked for rank through the LU.
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(N);
    if (!lu.isInvertible() || lu.rcond() < 1e-14)
        throw Error("rigid transformation: singular normal matrix (target geometry too weak)");
    const Eigen::MatrixXd Qxx = lu.inverse();

    T.residuals.resize(n);
    T.omega_sq = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const auto& c = centres[i];
        CentreResidual& res = T.residuals[i];
        res.residual = T.apply(c.epoch) - c.reference;
        T.omega_sq += res.residual.dot(P[i] * res.residual);
        // Q_vv = Q_ll − A·Q_xx·Aᵀ (Niemeier 2008, eq. 4.2-34); only the diagonal 3×3 blocks
        // are needed, since P is block-diagonal.
        const auto Ai = A[i].leftCols(u);
        const Eigen::Matrix3d Qll = P[i].inverse();
        res.cofactor = Qll - Ai * Qxx * Ai.transpose();
        res.sigma = res.cofactor.diagonal().cwiseMax(0.0).cwiseSqrt();
        for (int k = 0; k < 3; ++k)
            res.normalised(k) = res.sigma(k) > 0 ? res.residual(k) / res.sigma(k) : 0.0;
        // Redundancy numbers r_i = (Q_vv·P)_ii, summing to r (Förstner 1979; Niemeier 2008, §4.6).
        res.redundancy_share = (res.cofactor * P[i]).trace();
    }
    T.redundancy = static_cast<int>(3 * n) - u;
    T.variance_factor = T.redundancy > 0 ? T.omega_sq / T.redundancy : 0.0;
    T.covariance_factor = covariance_factor(params.scaling, T.variance_factor, T.redundancy);
    T.scale_estimated = params.estimate_scale;
    T.small_rotation_covariance.setZero();
    T.small_rotation_covariance.topLeftCorner(u, u) = T.covariance_factor * Qxx;

    finish_parameters(T);
    return T;
}

}  // namespace tlsmon::registration
