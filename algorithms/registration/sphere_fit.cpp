#include "algorithms/registration/sphere_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "core/statistics.hpp"

namespace tlsmon::registration {
namespace {

// The two centres of spheres of radius r through three points: on the normal of the
// triangle through its circumcentre o, at ±√(r² − ρ²), ρ the circumradius. Returns how
// many (0 when the points are nearly collinear or lie on a circle wider than the sphere).
int centres_through_three_points(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c, double r, Eigen::Vector3d out[2]) {
    const Eigen::Vector3d ab = b - a, ac = c - a;
    const Eigen::Vector3d n = ab.cross(ac);
    const double n2 = n.squaredNorm();
    if (n2 < 1e-18) return 0;
    // Circumcentre: a + (|ac|²·(n × ab) + |ab|²·(ac × n)) / (2|n|²).
    const Eigen::Vector3d o =
        a + (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) / (2.0 * n2);
    const double rho2 = (o - a).squaredNorm();
    if (rho2 > r * r) return 0;
    const Eigen::Vector3d h = std::sqrt(r * r - rho2) * n / std::sqrt(n2);
    out[0] = o + h;
    out[1] = o - h;
    return 2;
}

struct KnownRadiusFit {
    Eigen::Vector3d centre;
    Eigen::Matrix3d normal_matrix;     // N = Σ u·uᵀ
    Eigen::Matrix3d weighted_scatter;  // M = Σ v²·u·uᵀ
    double sum_v2 = 0.0;
    int iterations = 0;
    bool converged = false;
};

// Gauss–Newton for min Σ (|p − c| − r)² over c: the design row is −uᵀ with u = (p − c)/|p − c|
// (Förstner & Wrobel 2016, "Photogrammetric Computer Vision", §4.2, Gauss–Markov model).
KnownRadiusFit fit_known_radius(std::span<const Eigen::Vector3d> points,
                                const std::vector<std::uint32_t>& inliers, Eigen::Vector3d c,
                                double r, int max_iterations) {
    KnownRadiusFit fit;
    for (int it = 0; it <= max_iterations; ++it) {
        Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
        Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
        Eigen::Vector3d b = Eigen::Vector3d::Zero();
        double vv = 0.0;
        for (const std::uint32_t i : inliers) {
            const Eigen::Vector3d d = points[i] - c;
            const double dist = d.norm();
            const Eigen::Vector3d u = d / dist;
            const double f = dist - r;
            N.noalias() += u * u.transpose();
            M.noalias() += (f * f) * (u * u.transpose());
            b += u * f;
            vv += f * f;
        }
        fit.centre = c;
        fit.normal_matrix = N;
        fit.weighted_scatter = M;
        fit.sum_v2 = vv;
        fit.iterations = it;
        if (fit.converged || it == max_iterations) break;
        const Eigen::Vector3d dc = N.ldlt().solve(b);
        if (!dc.allFinite()) break;
        c += dc;
        // One more pass after convergence evaluates N and the residuals at the solution.
        if (dc.norm() < 1e-10) fit.converged = true;
    }
    return fit;
}

struct FreeRadiusFit {
    Eigen::Vector3d centre;
    double radius = 0.0;
    double radius_sigma = 0.0;
};

// Gauss–Newton for min Σ (|p − c| − r)² over c and r: design row [−uᵀ, −1].
FreeRadiusFit fit_free_radius(std::span<const Eigen::Vector3d> points,
                              const std::vector<std::uint32_t>& inliers, Eigen::Vector3d c,
                              double r, int max_iterations) {
    Eigen::Matrix4d N;
    double vv = 0.0;
    for (int it = 0; it <= max_iterations; ++it) {
        N.setZero();
        Eigen::Vector4d b = Eigen::Vector4d::Zero();
        vv = 0.0;
        for (const std::uint32_t i : inliers) {
            const Eigen::Vector3d d = points[i] - c;
            const double dist = d.norm();
            Eigen::Vector4d a;
            a << d / dist, 1.0;
            const double f = dist - r;
            N.noalias() += a * a.transpose();
            b += a * f;
            vv += f * f;
        }
        if (it == max_iterations) break;
        const Eigen::Vector4d dx = N.ldlt().solve(b);
        if (!dx.allFinite()) break;
        c += dx.head<3>();
        r += dx(3);
        if (dx.norm() < 1e-10) max_iterations = it + 1;  // one more pass at the solution
    }
    FreeRadiusFit out;
    out.centre = c;
    out.radius = r;
    const double redundancy = static_cast<double>(inliers.size()) - 4.0;
    const Eigen::Matrix4d Q = N.inverse();
    out.radius_sigma = redundancy > 0 ? std::sqrt(vv / redundancy * Q(3, 3)) : SphereFit::nan;
    return out;
}

std::string format(const char* fmt, double a, double b) {
    char buf[160];
    std::snprintf(buf, sizeof buf, fmt, a, b);
    return buf;
}

SphereFit fail(SphereFit fit, SphereFitStatus status, SphereFitReason reason, std::string detail) {
    fit.status = status;
    fit.reason = reason;
    fit.detail = std::move(detail);
    return fit;
}

}  // namespace

const char* describe(SphereFitReason reason) {
    switch (reason) {
        case SphereFitReason::none:
            return "found";
        case SphereFitReason::too_few_points:
            return "too few points near the predicted centre";
        case SphereFitReason::no_consensus:
            return "no sphere of the known radius near the prediction";
        case SphereFitReason::too_few_inliers:
            return "too few points on the sphere";
        case SphereFitReason::centre_far_from_prediction:
            return "centre too far from the prediction";
        case SphereFitReason::not_converged:
            return "least squares did not converge";
        case SphereFitReason::coverage_one_sided:
            return "visible part of the sphere too small or one-sided";
        case SphereFitReason::radius_check_failed:
            return "free-radius fit disagrees with the known radius";
        case SphereFitReason::residual_rms_too_large:
            return "residual RMS too large";
    }
    return "unknown";
}

SphereFit fit_sphere(std::span<const Eigen::Vector3d> points,
                     const Eigen::Vector3d& predicted_centre, const SphereFitParams& p) {
    SphereFit fit;
    fit.points = points.size();
    const std::size_t min_points = std::max<std::size_t>(p.min_points, 5);
    if (points.size() < min_points)
        return fail(fit, SphereFitStatus::not_found, SphereFitReason::too_few_points,
                    format("%.0f points, %.0f needed", static_cast<double>(points.size()),
                           static_cast<double>(min_points)));
    const double r = p.radius;
    const double t2 = p.inlier_threshold * p.inlier_threshold;

    // RANSAC with the MSAC cost Σ min(v², T²) (Fischler & Bolles 1981; Torr & Zisserman
    // 2000): candidates from 3 points and the known radius, kept only near the prediction.
    // A std::mt19937_64 stream is specified by the standard, so the samples are the same
    // on every platform.
    std::mt19937_64 rng(p.seed);
    const std::uint64_t n = points.size();
    Eigen::Vector3d best = predicted_centre;
    double best_cost = std::numeric_limits<double>::infinity();
    for (int k = 0; k < p.ransac_iterations; ++k) {
        const std::uint64_t i = rng() % n;
        std::uint64_t j = rng() % n, l = rng() % n;
        if (i == j || i == l || j == l) continue;
        Eigen::Vector3d cand[2];
        const int m = centres_through_three_points(points[i], points[j], points[l], r, cand);
        for (int s = 0; s < m; ++s) {
            if ((cand[s] - predicted_centre).norm() > p.max_centre_offset) continue;
            double cost = 0.0;
            for (const auto& q : points) {
                const double v = (q - cand[s]).norm() - r;
                cost += std::min(v * v, t2);
                if (cost >= best_cost) break;
            }
            if (cost < best_cost) {
                best_cost = cost;
                best = cand[s];
            }
        }
    }

    // The points within `bound` of the sphere about centre c, less the mount's cap.
    const double mount_cos = std::cos(p.mount_cap_deg * std::numbers::pi / 180.0);
    const bool has_mount = p.mount.squaredNorm() > 0 && p.mount_cap_deg > 0;
    const auto on_sphere = [&](const Eigen::Vector3d& c, double bound,
                               std::vector<std::uint32_t>& out) {
        out.clear();
        for (std::uint32_t i = 0; i < n; ++i) {
            const Eigen::Vector3d d = points[i] - c;
            const double norm = d.norm();
            if (std::fabs(norm - r) > bound) continue;
            if (has_mount && d.dot(p.mount) > mount_cos * norm) continue;
            out.push_back(i);
        }
    };
    std::vector<std::uint32_t> inliers;
    inliers.reserve(points.size());
    on_sphere(best, p.inlier_threshold, inliers);
    if (!std::isfinite(best_cost) || inliers.size() < min_points)
        return fail(fit, SphereFitStatus::not_found, SphereFitReason::no_consensus,
                    format("best consensus %.0f points, %.0f needed",
                           std::isfinite(best_cost) ? static_cast<double>(inliers.size()) : 0.0,
                           static_cast<double>(min_points)));

    // Refine, then re-select the inliers at k·σ̂ from the residuals' MAD (robust, Hampel
    // 1974), capped by the RANSAC threshold, until the set stops changing.
    KnownRadiusFit ls;
    Eigen::Vector3d c = best;
    std::vector<double> absv;
    absv.reserve(points.size());
    std::vector<std::uint32_t> next;
    next.reserve(points.size());
    for (int round = 0; round < 6; ++round) {
        ls = fit_known_radius(points, inliers, c, r, p.max_iterations);
        c = ls.centre;
        absv.clear();
        for (const std::uint32_t i : inliers) absv.push_back(std::fabs((points[i] - c).norm() - r));
        const double sigma = std::max(kMadToSigma * median_high(absv), p.min_noise);
        const double bound = std::min(p.outlier_k * sigma, p.inlier_threshold);
        on_sphere(c, bound, next);
        if (next == inliers) break;
        inliers.swap(next);
        if (inliers.size() < min_points) break;
    }
    fit.inliers = inliers.size();
    if (inliers.size() < min_points)
        return fail(fit, SphereFitStatus::not_found, SphereFitReason::too_few_inliers,
                    format("%.0f inliers, %.0f needed", static_cast<double>(inliers.size()),
                           static_cast<double>(min_points)));
    ls = fit_known_radius(points, inliers, c, r, p.max_iterations);

    const double m = static_cast<double>(inliers.size());
    fit.centre = ls.centre;
    fit.iterations = ls.iterations;
    fit.rms = std::sqrt(ls.sum_v2 / m);
    // A posteriori variance factor s0² = vᵀv/(n − 3) and Σ_cc = s0²·N⁻¹ (Niemeier 2008,
    // "Ausgleichungsrechnung", 2nd ed., §4.2: Gauss–Markov model, eqs. 4.2-27 and 4.2-30).
    const double s02 = ls.sum_v2 / (m - 3.0);
    fit.sigma0 = std::sqrt(s02);
    const Eigen::Matrix3d Ninv = ls.normal_matrix.inverse();
    fit.centre_covariance_homoscedastic = s02 * Ninv;
    // The points are not equally precise: a TLS's noise is along the ray, so a point's
    // distance to the sphere varies with σ_r·cos(incidence), largest on the front of the cap,
    // which is what fixes the centre along the line of sight. s0²·N⁻¹ averages that away (too
    // wide across the line of sight by up to 25 %); the heteroscedasticity-consistent covariance
    // N⁻¹·(Σ v²·u·uᵀ)·N⁻¹·n/(n − 3) (White 1980; HC1 of MacKinnon & White 1985) needs no
    // noise model and is what is reported.
    fit.centre_covariance = m / (m - 3.0) * Ninv * ls.weighted_scatter * Ninv;
    // Geometry of the cap: the smallest eigenvalue of N/n (the unit vectors' second moment).
    fit.coverage =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(ls.normal_matrix / m, Eigen::EigenvaluesOnly)
            .eigenvalues()(0);

    const FreeRadiusFit fr = fit_free_radius(points, inliers, ls.centre, r, p.max_iterations);
    fit.free_centre = fr.centre;
    fit.free_radius = fr.radius;
    fit.free_radius_sigma = fr.radius_sigma;
    fit.radius_deviation = fr.radius - r;

    const double offset = (fit.centre - predicted_centre).norm();
    if (offset > p.max_centre_offset)
        return fail(fit, SphereFitStatus::not_found, SphereFitReason::centre_far_from_prediction,
                    format("centre %.4f m from the prediction, at most %.4f m", offset,
                           p.max_centre_offset));
    if (!ls.converged || !fit.centre_covariance.allFinite())
        return fail(fit, SphereFitStatus::bad_fit, SphereFitReason::not_converged,
                    format("%.0f iterations, limit %.0f", ls.iterations, p.max_iterations));
    if (!(fit.coverage >= p.min_coverage))
        return fail(fit, SphereFitStatus::bad_fit, SphereFitReason::coverage_one_sided,
                    format("coverage %.4f, at least %.4f", fit.coverage, p.min_coverage));
    if (!(std::fabs(fit.radius_deviation) <= p.max_radius_deviation))
        return fail(fit, SphereFitStatus::bad_fit, SphereFitReason::radius_check_failed,
                    format("free radius deviates by %.4f m, at most %.4f m", fit.radius_deviation,
                           p.max_radius_deviation));
    if (!(fit.rms <= p.max_rms))
        return fail(fit, SphereFitStatus::bad_fit, SphereFitReason::residual_rms_too_large,
                    format("RMS %.4f m, at most %.4f m", fit.rms, p.max_rms));
    fit.status = SphereFitStatus::found;
    fit.reason = SphereFitReason::none;
    return fit;
}

}  // namespace tlsmon::registration
