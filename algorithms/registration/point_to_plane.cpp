#include "algorithms/registration/point_to_plane.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include "algorithms/cell_key.hpp"
#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/so3.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::registration {

namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

}  // namespace

RigidTransform rigid_transform_from(const Eigen::Matrix3d& rotation,
                                    const Eigen::Vector3d& translation,
                                    const Covariance6& small_rotation_covariance) {
    RigidTransform T;
    T.rotation = rotation;
    T.translation = translation;
    const Eigen::Vector3d e = euler_from_rotation(rotation);
    T.omega = e(0);
    T.phi = e(1);
    T.kappa = e(2);
    T.quaternion = Eigen::Quaterniond(rotation).normalized();
    if (T.quaternion.w() < 0) T.quaternion.coeffs() *= -1.0;
    T.small_rotation_covariance.setZero();
    T.small_rotation_covariance.topLeftCorner<6, 6>() = small_rotation_covariance;
    // θ = M·(dω, dφ, dκ), M = [R_z·R_y·e_x | R_z·e_y | e_z] (Förstner & Wrobel 2016, §8.1.3);
    // Σ_euler = J·Σ_θ·Jᵀ with J = blockdiag(M⁻¹, I).
    const Eigen::Matrix3d Rz = Eigen::AngleAxisd(T.kappa, Eigen::Vector3d::UnitZ()).matrix();
    const Eigen::Matrix3d Ry = Eigen::AngleAxisd(T.phi, Eigen::Vector3d::UnitY()).matrix();
    Eigen::Matrix3d M;
    M.col(0) = Rz * Ry * Eigen::Vector3d::UnitX();
    M.col(1) = Rz * Eigen::Vector3d::UnitY();
    M.col(2) = Eigen::Vector3d::UnitZ();
    ParameterCovariance J = ParameterCovariance::Identity();
    J.topLeftCorner<3, 3>() = M.inverse();
    T.covariance = J * T.small_rotation_covariance * J.transpose();
    return T;
}

namespace {

PointToPlaneFit fit_pairs(std::span<const PointPlanePair> pairs, const Eigen::Matrix4d& start,
                          const PointToPlaneParams& params);

}  // namespace

// In the frame where `floor` is the identity (whitened by its Cholesky factor L), the
// eigenvalues of `other` clamped below at 1.
Eigen::MatrixXd larger_of(const Eigen::MatrixXd& floor, const Eigen::MatrixXd& other) {
    const Eigen::LLT<Eigen::MatrixXd> llt(floor);
    if (llt.info() != Eigen::Success) return other;
    const Eigen::MatrixXd L = llt.matrixL();
    const Eigen::MatrixXd Linv = L.inverse();
    const Eigen::MatrixXd W = Linv * other * Linv.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (W + W.transpose()));
    const Eigen::VectorXd d = es.eigenvalues().cwiseMax(1.0);
    return L * es.eigenvectors() * d.asDiagonal() * es.eigenvectors().transpose() * L.transpose();
}

Covariance6 larger_of(const Covariance6& floor, const Covariance6& other) {
    return larger_of(Eigen::MatrixXd(floor), Eigen::MatrixXd(other));
}

PointToPlaneFit fit_point_to_plane(std::span<const PointPlanePair> pairs,
                                   const Eigen::Matrix4d& start, const PointToPlaneParams& params) {
    PointToPlaneFit first = fit_pairs(pairs, start, params);
    if (!(params.outlier_k > 0)) return first;
    const Eigen::Matrix4d H = first.transform.matrix();
    const Eigen::Matrix3d R = H.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = H.topRightCorner<3, 1>();
    std::vector<double> v;
    v.reserve(pairs.size());
    // Standardised distances √p·v: a pair is an outlier against its own σ.
    for (const auto& p : pairs)
        v.push_back(std::sqrt(p.weight) * p.normal.dot(R * p.epoch + t - p.reference));
    std::vector<double> a(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) a[i] = std::fabs(v[i]);
    const double sigma = std::max(params.min_sigma, kMadToSigma * median_high(std::move(a)));
    std::vector<PointPlanePair> kept;
    kept.reserve(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        if (std::fabs(v[i]) <= params.outlier_k * sigma) kept.push_back(pairs[i]);
    }
    if (kept.size() == pairs.size()) return first;
    PointToPlaneFit out = fit_pairs(kept, H, params);
    out.outliers = pairs.size() - kept.size();
    return out;
}

namespace {

PointToPlaneFit fit_pairs(std::span<const PointPlanePair> pairs, const Eigen::Matrix4d& start,
                          const PointToPlaneParams& params) {
    const std::size_t n = pairs.size();
    if (n < 7) {
        throw Error("point-to-plane fit: " + std::to_string(n) + " pairs (at least 7 needed)");
    }
    Eigen::Matrix3d R = start.topLeftCorner<3, 3>();
    Eigen::Vector3d t = start.topRightCorner<3, 1>();
    const auto row = [&](const PointPlanePair& p, double& v) {
        const Eigen::Vector3d y = R * p.epoch;
        v = p.normal.dot(y + t - p.reference);
        Vector6 a;
        a.head<3>() = y.cross(p.normal);
        a.tail<3>() = p.normal;
        return a;
    };
    Covariance6 N;
    for (int it = 0; it <= std::max(0, params.iterations); ++it) {
        N.setZero();
        Vector6 b = Vector6::Zero();
        for (const auto& p : pairs) {
            double v = 0;
            const Vector6 a = row(p, v);
            N.selfadjointView<Eigen::Lower>().rankUpdate(a, p.weight);
            b += p.weight * v * a;
        }
        N = N.selfadjointView<Eigen::Lower>();
        if (it == params.iterations) break;  // N at the solution, for the covariance
        const Eigen::LDLT<Covariance6> ldlt(N);
        const Vector6 dx = -ldlt.solve(b);
        if (ldlt.info() != Eigen::Success || !dx.allFinite()) {
            throw Error(
                "point-to-plane fit: singular normal matrix (the stable regions' "
                "surfaces do not hold every direction)");
        }
        R = exp_so3(dx.head<3>()) * R;
        t += dx.tail<3>();
    }
    const Eigen::Matrix<double, 6, 1> scale = N.diagonal().cwiseSqrt().cwiseInverse();
    const Covariance6 Ns = scale.asDiagonal() * N * scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Covariance6> es(Ns);
    PointToPlaneFit out;
    out.pairs = n;
    out.condition = es.eigenvalues()(5) / std::max(es.eigenvalues()(0), 1e-300);
    if (!(es.eigenvalues()(0) > 1e-12)) {
        throw Error(
            "point-to-plane fit: singular normal matrix (the stable regions' surfaces "
            "do not hold every direction)");
    }
    const Covariance6 Ninv = N.inverse();
    // Residuals, and per cell the scores g_k = Σ p·a·v, b_k = Σ p·a, Σ p, Σ p·v and Σ p·v².
    struct Cell {
        Vector6 score = Vector6::Zero(), b = Vector6::Zero();
        Covariance6 normal = Covariance6::Zero();  // N_c = Σ p·a·aᵀ
        double w = 0, wv = 0, wvv = 0;
    };
    std::unordered_map<std::uint64_t, Cell> cells;
    double vv = 0, pvv = 0;
    for (const auto& p : pairs) {
        double v = 0;
        const Vector6 a = row(p, v);
        vv += v * v;
        pvv += p.weight * v * v;
        Cell& cell = cells[cell_key(p.reference - params.cell_origin, params.cluster_size)];
        cell.score += p.weight * v * a;
        cell.b += p.weight * a;
        cell.normal.selfadjointView<Eigen::Lower>().rankUpdate(a, p.weight);
        cell.w += p.weight;
        cell.wv += p.weight * v;
        cell.wvv += p.weight * v * v;
    }
    out.rms = std::sqrt(vv / n);
    out.variance_factor = pvv / (n - 6);
    out.independent = out.variance_factor * Ninv;
    // One-way random effects of the cells: v_i = u_c + e_i, e_i of variance σ_e²/p_i and u_c,
    // common to the pairs of cell c, of variance τ². σ_e² from the spread within the cells,
    // Σ_c Σ_i p·(v − r̄_c)²/(n − C). τ² by the ANOVA estimator of unbalanced data (Henderson's
    // method I; Searle, Casella & McCulloch 1992, ch. 5): the cells' sum of squares
    // Σ_c w_c·r̄_c² = Σ_c s_c²/w_c (s_c = Σ_{i∈c} p·v, w_c = Σ p) equated with its expectation
    // under the model, taken exactly through the fit that made the residuals (v = ṽ − A·δ,
    // δ = N⁻¹·Aᵀ·P·ṽ):
    //   E[s_c²] = τ²·(w_c² − 2·w_c·h_c + b_cᵀ·N⁻¹·B·N⁻¹·b_c) + σ_e²·(w_c − h_c),
    // h_c = b_cᵀ·N⁻¹·b_c, B = Σ_c b_c·b_cᵀ. The estimator's covariance is then
    // N⁻¹·(σ_e²·N + τ²·B)·N⁻¹. Unlike the sandwich it pools τ² over every cell, so a direction
    // only a few cells hold still gets it; weighted by w_c, the cells that weigh in the
    // estimate weigh in τ² (each cell's mean alike, the far grazing ground's many sparse cells
    // set τ² and padded the faces' directions 1.4 times; docs/registration.md, step 5).
    const double C = static_cast<double>(cells.size());
    out.cell_effect = out.independent;
    if (C > 6 && static_cast<double>(n) > C) {
        double within = 0;
        for (const auto& [key, cell] : cells) within += cell.wvv - cell.wv * cell.wv / cell.w;
        const double sigma_e2 = std::max(0.0, within) / (static_cast<double>(n) - C);
        Covariance6 B = Covariance6::Zero(), B_per_w = Covariance6::Zero();
        double between = 0, tau_coefficient = 0, sigma_coefficient = 0;
        for (const auto& [key, cell] : cells) {
            const double h = cell.b.dot(Ninv * cell.b);
            between += cell.wv * cell.wv / cell.w;
            tau_coefficient += cell.w - 2 * h;
            sigma_coefficient += 1 - h / cell.w;
            B.selfadjointView<Eigen::Lower>().rankUpdate(cell.b);
            B_per_w.selfadjointView<Eigen::Lower>().rankUpdate(cell.b, 1 / cell.w);
        }
        B = B.selfadjointView<Eigen::Lower>();
        B_per_w = B_per_w.selfadjointView<Eigen::Lower>();
        tau_coefficient += (Ninv * B_per_w * Ninv * B).trace();
        // Only a significant cell effect (Σ w_c·r̄_c²/σ_e² ~ χ²(C − 6) without one, α 5 %):
        // the moment estimate, cut at zero, is otherwise above zero half the time and pads the
        // σ of independent noise by a quarter.
        const bool significant =
            sigma_e2 > 0 && between / sigma_e2 > chi_square_quantile(0.95, C - 6);
        const double tau2 =
            significant && tau_coefficient > 0
                ? std::max(0.0, (between - sigma_e2 * sigma_coefficient) / tau_coefficient)
                : 0.0;
        out.cell_sigma = std::sqrt(tau2);
        out.cell_effect = sigma_e2 * Ninv + tau2 * Ninv * B * Ninv;
        out.cell_effect = 0.5 * (out.cell_effect + out.cell_effect.transpose());
    }
    const std::size_t c = cells.size();
    out.clusters = c;
    Covariance6 meat = Covariance6::Zero();
    for (const auto& [key, cell] : cells) meat += cell.score * cell.score.transpose();
    Covariance6 reported =
        params.cell_effect ? larger_of(out.independent, out.cell_effect) : out.independent;
    if (c >= 2) {
        const double small_sample = (double(c) / (c - 1)) * (double(n - 1) / (n - 6));
        out.clustered = small_sample * Ninv * meat * Ninv;
        out.clustered = 0.5 * (out.clustered + out.clustered.transpose());
        reported = larger_of(reported, out.clustered);
        // Bell–McCaffrey degrees of freedom of ℓᵀ·Σ_c·ℓ under independent residuals: with
        // G = (I − H)·blockdiag(X_c·N⁻¹·ℓ), dof = (tr GᵀG)²/‖GᵀG‖²_F, where
        // GᵀG = diag(ℓᵀN⁻¹N_cN⁻¹ℓ) − QᵀN⁻¹Q, Q's columns N_c·N⁻¹·ℓ.
        for (int k = 0; k < 6; ++k) {
            const Vector6 m = Ninv.col(k);
            Covariance6 S = Covariance6::Zero();
            double trace_diag = 0, diag2 = 0, cross = 0;
            for (const auto& [key, cell] : cells) {
                const Vector6 q = cell.normal.selfadjointView<Eigen::Lower>() * m;
                const double d = m.dot(q);
                const double h = q.dot(Ninv * q);
                trace_diag += d;
                diag2 += d * d;
                cross += d * h;
                S += q * q.transpose();
            }
            const Covariance6 NS = Ninv * S;
            const double trace = trace_diag - NS.trace();
            const double frob = diag2 - 2 * cross + (NS * NS).trace();
            out.clustered_dof(k) = frob > 0 ? trace * trace / frob : 1e9;
        }
    } else {
        out.clustered = out.independent;
    }
    double inflation = 1.0;
    for (int k = 0; k < 6; ++k) {
        inflation = std::max(inflation, std::sqrt(reported(k, k) / out.independent(k, k)));
    }
    out.inflation = inflation;
    out.transform = rigid_transform_from(R, t, reported);
    out.transform.variance_factor = out.variance_factor;
    out.transform.redundancy = static_cast<int>(n) - 6;
    out.transform.iterations = params.iterations;
    return out;
}

}  // namespace

namespace {

// b as a correction δ of a: R_b = exp([δθ]×)·R_a, t_b = t_a + δt.
Vector6 correction(const RigidTransform& a, const RigidTransform& b) {
    const Eigen::AngleAxisd dr(b.rotation * a.rotation.transpose());
    Vector6 d;
    d.head<3>() = dr.angle() * dr.axis();
    d.tail<3>() = b.translation - a.translation;
    return d;
}

}  // namespace

double transform_difference_statistic(const RigidTransform& a, const RigidTransform& b) {
    const Vector6 d = correction(a, b);
    const Covariance6 S = a.small_rotation_covariance.topLeftCorner<6, 6>() +
                          b.small_rotation_covariance.topLeftCorner<6, 6>();
    return d.dot(S.ldlt().solve(d));
}

RigidTransform combine_transforms(const RigidTransform& a, const RigidTransform& b) {
    const Covariance6 Sa = a.small_rotation_covariance.topLeftCorner<6, 6>();
    const Covariance6 Sb = b.small_rotation_covariance.topLeftCorner<6, 6>();
    const Eigen::LDLT<Covariance6> la(Sa), lb(Sb);
    const Covariance6 Pa = la.solve(Covariance6::Identity());
    const Covariance6 Pb = lb.solve(Covariance6::Identity());
    if (la.info() != Eigen::Success || lb.info() != Eigen::Success || !Pa.allFinite() ||
        !Pb.allFinite()) {
        throw Error("combining two registrations: a covariance is singular");
    }
    const Vector6 d = correction(a, b);
    const Covariance6 P = Pa + Pb;
    const Eigen::LDLT<Covariance6> lp(P);
    const Covariance6 S = lp.solve(Covariance6::Identity());
    const Vector6 dc = S * (Pb * d);
    RigidTransform c =
        rigid_transform_from(exp_so3(dc.head<3>()) * a.rotation, a.translation + dc.tail<3>(),
                             0.5 * (S + S.transpose()));
    c.variance_factor = a.variance_factor;
    c.redundancy = a.redundancy + b.redundancy;
    c.residuals = a.residuals;
    return c;
}

}  // namespace tlsmon::registration
