#include "algorithms/registration/target_tests.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {
namespace {

struct OutlierTest {
    double statistic = 0.0;
    double critical = 0.0;
    int dof = 0;
};

// T_i = v_iᵀ·Q_vv,ii⁺·v_i over the non-null directions of the target's residual cofactor:
// the test of a 3-D bias in one target, C = the target's rows, in
// T = vᵀPC·(CᵀP·Q_vv·PC)⁻¹·CᵀPv (Förstner 1983, "Reliability and discernability of extended
// Gauss-Markov models"; Teunissen 2000, "Testing theory", §4.3), which reduces to this for a
// block-diagonal P. A direction the transformation absorbs completely (eigenvalue ~ 0) can
// show no bias and is left out of the degrees of freedom.
OutlierTest quadratic_form_test(const CentreResidual& r, const Eigen::Matrix3d& Qll, double alpha) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(r.cofactor);
    const double floor = 1e-9 * Qll.trace();
    OutlierTest t;
    for (int k = 0; k < 3; ++k) {
        const double lambda = eig.eigenvalues()(k);
        if (lambda <= floor) continue;
        const double proj = eig.eigenvectors().col(k).dot(r.residual);
        t.statistic += proj * proj / lambda;
        ++t.dof;
    }
    t.critical = t.dof > 0 ? chi_square_quantile(1.0 - alpha, t.dof) : 0.0;
    return t;
}

// Baarda 1968, "A testing procedure for use in geodetic networks": w_j = e_jᵀPv /
// √(e_jᵀ·P·Q_vv·P·e_j), for correlated observations as in Förstner 1983; for a diagonal
// Q_ll it is v_j / σ_vj. Two-sided, critical value Φ⁻¹(1 − α/2).
OutlierTest largest_w_test(const CentreResidual& r, const Eigen::Matrix3d& P, double alpha) {
    const Eigen::Vector3d Pv = P * r.residual;
    const Eigen::Matrix3d M = P * r.cofactor * P;
    OutlierTest t;
    for (int k = 0; k < 3; ++k) {
        if (!(M(k, k) > 1e-9 * P(k, k))) continue;
        t.statistic = std::max(t.statistic, std::fabs(Pv(k)) / std::sqrt(M(k, k)));
        t.dof = 1;
    }
    t.critical = normal_quantile(1.0 - alpha / 2.0);
    return t;
}

// Minimal detectable bias in the least favourable direction: a bias ∇ of target i shifts the
// residuals by −Q_vv·P·C·∇, which gives the test of target i the noncentrality
// λ = ∇ᵀ·P_i·Q_vv,ii·P_i·∇ (Baarda 1968; Förstner 1983). It is found with probability
// `power` when λ ≥ λ0(α, power, dof), so the largest undetected bias over directions is
// √(λ0 / μ_min), μ_min the smallest eigenvalue of P_i·Q_vv,ii·P_i (for the w-test, λ0 is that
// of one degree of freedom: δ0² = 4.13² for α = 0.1 %, power 80 %).
void minimal_detectable_bias(const CentreResidual& r, const Eigen::Matrix3d& P, double lambda0,
                             TargetVerdict& v) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(P * r.cofactor * P);
    const double mu = eig.eigenvalues()(0);
    v.weakest_direction = eig.eigenvectors().col(0);
    v.minimal_detectable_bias = mu > 1e-9 * eig.eigenvalues()(2)
                                    ? std::sqrt(lambda0 / mu)
                                    : std::numeric_limits<double>::infinity();
}

std::string text(const char* fmt, double a, double b = 0.0, double c = 0.0) {
    char buf[200];
    std::snprintf(buf, sizeof buf, fmt, a, b, c);
    return buf;
}

}  // namespace

const char* describe(TargetUse use) {
    switch (use) {
        case TargetUse::used:
            return "used";
        case TargetUse::not_usable:
            return "not usable in this epoch";
        case TargetUse::excluded_outlier:
            return "excluded: failed the outlier test";
        case TargetUse::suspect:
            return "suspect: failed the outlier test, too few targets to exclude it";
    }
    return "unknown";
}

const char* describe(RegistrationStatus status) {
    switch (status) {
        case RegistrationStatus::accepted:
            return "accepted";
        case RegistrationStatus::accepted_scaled:
            return "accepted, covariance scaled by the variance factor";
        case RegistrationStatus::global_test_failed:
            return "global test failed";
        case RegistrationStatus::too_few_targets:
            return "refused: too few targets";
        case RegistrationStatus::degenerate_geometry:
            return "refused: targets nearly on a line";
        case RegistrationStatus::outlier_not_excludable:
            return "refused: outlier cannot be excluded";
        case RegistrationStatus::outlier_not_identifiable:
            return "refused: outlier cannot be attributed to one target";
        case RegistrationStatus::planes_refused:
            return "refused: no registration on planes";
        case RegistrationStatus::stable_areas_refused:
            return "refused: no registration on stable areas";
    }
    return "unknown";
}

double spread_about_line(std::span<const Eigen::Vector3d> points) {
    if (points.size() < 2) return 0.0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : points) mean += p;
    mean /= static_cast<double>(points.size());
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (const auto& p : points) S.noalias() += (p - mean) * (p - mean).transpose();
    S /= static_cast<double>(points.size());
    const Eigen::Vector3d l =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S, Eigen::EigenvaluesOnly).eigenvalues();
    return std::sqrt(std::max(0.0, l(0) + l(1)));
}

TestedRegistration register_with_tests(std::span<const TargetPair> targets,
                                       const TargetTestParams& params) {
    if (!(params.global_alpha > 0 && params.global_alpha < 1) ||
        !(params.target_alpha > 0 && params.target_alpha < 1))
        throw Error("registration tests: alpha must lie in (0, 1)");
    if (!(params.global_reject_alpha > 0 && params.global_reject_alpha <= params.global_alpha))
        throw Error("registration tests: global_reject_alpha must lie in (0, global_alpha]");
    if (!(params.power > 0 && params.power < 1))
        throw Error("registration tests: power must lie in (0, 1)");
    const std::size_t min_targets = std::max<std::size_t>(params.min_targets, 3);
    TestedRegistration out;
    out.targets.resize(targets.size());
    for (std::size_t i = 0; i < targets.size(); ++i)
        out.targets[i].use = targets[i].usable ? TargetUse::used : TargetUse::not_usable;

    std::vector<std::size_t> used;
    std::vector<CentreObservation> centres;
    std::vector<Eigen::Vector3d> positions;
    std::vector<OutlierTest> drops;
    // λ0 per degrees of freedom of the test (1–3), computed once.
    double lambda0_cache[4] = {0, 0, 0, 0};
    auto lambda0 = [&](int dof) {
        if (params.statistic == OutlierStatistic::largest_normalised_residual) dof = 1;
        if (lambda0_cache[dof] == 0.0)
            lambda0_cache[dof] = detectable_noncentrality(params.target_alpha, params.power, dof);
        return lambda0_cache[dof];
    };
    auto finish = [&](RegistrationStatus status, std::string reason) {
        out.status = status;
        out.reason = std::move(reason);
        if (out.transform)
            for (std::size_t i = 0; i < targets.size(); ++i)
                if (out.targets[i].use != TargetUse::not_usable)
                    out.targets[i].residual = centre_residual(*out.transform, targets[i].centres);
        return out;
    };

    for (int round = 1;; ++round) {
        used.clear();
        centres.clear();
        positions.clear();
        for (std::size_t i = 0; i < targets.size(); ++i)
            if (out.targets[i].use == TargetUse::used) {
                used.push_back(i);
                centres.push_back(targets[i].centres);
                positions.push_back(targets[i].centres.reference);
            }
        if (used.size() < min_targets)
            return finish(RegistrationStatus::too_few_targets,
                          text("%.0f usable targets, at least %.0f needed",
                               static_cast<double>(used.size()), static_cast<double>(min_targets)));
        out.spread = spread_about_line(positions);
        if (out.spread < params.min_spread) {
            out.transform.reset();  // an earlier round's adjustment is not this geometry's
            return finish(
                RegistrationStatus::degenerate_geometry,
                text("the %.0f used targets lie within %.3f m of a line, at least %.3f m needed",
                     static_cast<double>(used.size()), out.spread, params.min_spread));
        }
        try {
            out.transform = estimate_rigid_transform(centres, params.adjustment);
        } catch (const Error& e) {
            out.transform.reset();
            return finish(RegistrationStatus::degenerate_geometry, e.what());
        }
        out.rounds = round;
        const RigidTransform& T = *out.transform;

        // Data snooping: test every used target, take the one furthest beyond its critical
        // value (Baarda 1968; iterated, one target per round, as in Niemeier 2008 §13.4).
        std::ptrdiff_t worst = -1;
        std::size_t worst_k = 0;
        double worst_ratio = 1.0;
        drops.assign(used.size(), OutlierTest{});
        for (std::size_t k = 0; k < used.size(); ++k) {
            const CentreObservation& c = centres[k];
            const Eigen::Matrix3d Qll = c.reference_covariance + T.scale * T.scale * T.rotation *
                                                                     c.epoch_covariance *
                                                                     T.rotation.transpose();
            const Eigen::Matrix3d P = Qll.inverse();
            drops[k] = quadratic_form_test(T.residuals[k], Qll, params.target_alpha);
            const OutlierTest t = params.statistic == OutlierStatistic::target_quadratic_form
                                      ? drops[k]
                                      : largest_w_test(T.residuals[k], P, params.target_alpha);
            TargetVerdict& v = out.targets[used[k]];
            v.statistic = t.statistic;
            v.critical = t.critical;
            v.dof = t.dof;
            minimal_detectable_bias(T.residuals[k], P, t.dof > 0 ? lambda0(t.dof) : 0.0, v);
            if (t.dof > 0 && t.statistic > t.critical && t.statistic / t.critical > worst_ratio) {
                worst_ratio = t.statistic / t.critical;
                worst = static_cast<std::ptrdiff_t>(used[k]);
                worst_k = k;
            }
        }
        if (worst < 0) break;
        TargetVerdict& w = out.targets[static_cast<std::size_t>(worst)];
        // Separability (Förstner 1983): the worst target is excluded only if leaving out any
        // other one instead would still leave a misfit. T_j is the drop of Ω when target j is
        // left out, so Ω − T_j is what that alternative leaves, tested like the global test.
        for (std::size_t k = 0; k < used.size(); ++k) {
            if (k == worst_k || drops[k].dof == 0) continue;
            const int r_left = T.redundancy - drops[k].dof;
            const double left = std::max(0.0, T.omega_sq - drops[k].statistic);
            if (r_left <= 0 || left <= chi_square_quantile(1.0 - params.global_alpha, r_left)) {
                w.use = TargetUse::suspect;
                out.targets[used[k]].use = TargetUse::suspect;
                return finish(RegistrationStatus::outlier_not_identifiable,
                              text("target %.0f fails its outlier test (%.1f > %.1f), ",
                                   static_cast<double>(worst), w.statistic, w.critical) +
                                  text("but leaving out target %.0f instead fits as well",
                                       static_cast<double>(used[k])));
            }
        }
        if (used.size() - 1 < min_targets) {
            w.use = TargetUse::suspect;
            return finish(
                RegistrationStatus::outlier_not_excludable,
                text("target %.0f fails its outlier test (%.1f > %.1f); excluding it would "
                     "leave fewer than the minimum of targets",
                     static_cast<double>(worst), w.statistic, w.critical));
        }
        w.use = TargetUse::excluded_outlier;
        w.excluded_in_round = round;
    }

    // Global test: Ω ~ χ²(r) when the centres' covariances are right (σ0 = 1); one-sided,
    // since a variance factor below 1 only says the covariances are cautious (Niemeier 2008,
    // §4.5; Koch 1999, "Parameter estimation and hypothesis testing", §4.2).
    const RigidTransform& T = *out.transform;
    out.global.omega_sq = T.omega_sq;
    out.global.redundancy = T.redundancy;
    out.global.variance_factor = T.variance_factor;
    out.global.critical = chi_square_quantile(1.0 - params.global_alpha, T.redundancy);
    out.global.passed = T.omega_sq <= out.global.critical;
    out.global.hard_limit = chi_square_quantile(1.0 - params.global_reject_alpha, T.redundancy);
    if (!out.global.passed && T.omega_sq <= out.global.hard_limit) {
        // Every target passed its outlier test, so no single target is to blame: the
        // centres' covariances are too small for this epoch as a whole (the air, a breeze on
        // a mast). The a-posteriori variance factor is the estimate of by how much (Niemeier
        // 2008, §4.5; Koch 1999, §4.2.3), so the covariance is scaled by s0² and the epoch
        // accepted, flagged. The hard limit keeps a gross misfit a refusal.
        // With the t expansion of its redundancy (rigid_transform.hpp, covariance_factor).
        RigidTransform& S = *out.transform;
        const double wanted = S.variance_factor * t_expansion(S.redundancy);
        if (S.covariance_factor < wanted) {
            const double k = wanted / S.covariance_factor;
            S.covariance *= k;
            S.small_rotation_covariance *= k;
            S.covariance_factor = wanted;
        }
        return finish(RegistrationStatus::accepted_scaled,
                      text("Omega %.2f > chi2 critical %.2f: covariance scaled by the variance "
                           "factor %.2f",
                           T.omega_sq, out.global.critical, T.variance_factor) +
                          text(" (hard limit %.2f)", out.global.hard_limit / T.redundancy));
    }
    if (!out.global.passed)
        return finish(RegistrationStatus::global_test_failed,
                      text("Omega %.2f > chi2 critical %.2f (variance factor %.2f, ", T.omega_sq,
                           out.global.critical, T.variance_factor) +
                          text("above its hard limit %.2f)", out.global.hard_limit / T.redundancy));
    return finish(RegistrationStatus::accepted, "");
}

}  // namespace tlsmon::registration
