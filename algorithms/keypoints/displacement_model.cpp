#include "algorithms/keypoints/displacement_model.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <vector>

#include "algorithms/keypoints/outlier_filters.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::keypoints {
namespace {

constexpr int kTerms = static_cast<int>(kModelTerms.size());
// A column whose QR pivot falls below this share of the largest one is not carried by the
// (t, z) points. The scaled monomials are O(1), so exact dependence shows as ~1e-15.
constexpr double kRankThreshold = 1e-9;

// The monomials u^p w^q of kModelTerms at one point.
Eigen::Matrix<double, 1, 10> monomials(double u, double w) {
    std::array<double, 4> up{1, u, u * u, u * u * u}, wp{1, w, w * w, w * w * w};
    Eigen::Matrix<double, 1, 10> row;
    for (int k = 0; k < kTerms; ++k) row[k] = up[kModelTerms[k].p] * wp[kModelTerms[k].q];
    return row;
}

// Centre and half-width of a range (half-width 1 when it is empty).
std::pair<double, double> centre_and_scale(double lo, double hi) {
    const double half = (hi - lo) / 2;
    return {lo + half, half > 0 ? half : 1.0};
}

double binomial(int n, int k) {
    double r = 1;
    for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
    return r;
}

}  // namespace

double DisplacementModel::operator()(double t, double z) const {
    return monomials((t - t_centre) / t_scale, (z - z_centre) / z_scale).dot(coefficients);
}

ModelCoefficients DisplacementModel::raw_coefficients() const {
    // a_pq ((t − t0)/ts)^p ((z − z0)/zs)^q expanded binomially into c_ij t^i z^j.
    ModelCoefficients raw = ModelCoefficients::Zero();
    const auto index = [](int i, int j) {
        for (int k = 0; k < kTerms; ++k)
            if (kModelTerms[k].p == i && kModelTerms[k].q == j) return k;
        return -1;
    };
    for (int k = 0; k < kTerms; ++k) {
        const auto [p, q] = kModelTerms[k];
        const double a = coefficients[k] / (std::pow(t_scale, p) * std::pow(z_scale, q));
        for (int i = 0; i <= p; ++i)
            for (int j = 0; j <= q; ++j)
                raw[index(i, j)] += a * binomial(p, i) * std::pow(-t_centre, p - i) *
                                    binomial(q, j) * std::pow(-z_centre, q - j);
    }
    return raw;
}

DisplacementModel fit_displacement_model(std::span<const ModelObservation> observations,
                                         const ModelParameters& parameters) {
    if (!(parameters.tolerance > 0) || !(parameters.epsilon > 0))
        throw Error("displacement model: tolerance and epsilon must be positive");
    const std::size_t n = observations.size();
    for (std::size_t i = 0; i < n; ++i) {
        const auto& o = observations[i];
        if (!std::isfinite(o.t) || !std::isfinite(o.z) || !std::isfinite(o.d))
            throw Error("displacement model: observation " + std::to_string(i) +
                        " (t, z, d) is not finite");
    }
    DisplacementModel model;
    model.observations = n;
    if (n < static_cast<std::size_t>(kTerms)) {
        model.undefined_reason =
            std::to_string(n) + " observations: the cubic needs at least " + std::to_string(kTerms);
        return model;
    }
    double t_lo = observations[0].t, t_hi = t_lo, z_lo = observations[0].z, z_hi = z_lo;
    for (const auto& o : observations) {
        t_lo = std::min(t_lo, o.t), t_hi = std::max(t_hi, o.t);
        z_lo = std::min(z_lo, o.z), z_hi = std::max(z_hi, o.z);
    }
    std::tie(model.t_centre, model.t_scale) = centre_and_scale(t_lo, t_hi);
    std::tie(model.z_centre, model.z_scale) = centre_and_scale(z_lo, z_hi);

    const Eigen::Index rows = static_cast<Eigen::Index>(n);
    Eigen::MatrixXd X(rows, kTerms);
    Eigen::VectorXd d(rows);
    for (Eigen::Index i = 0; i < rows; ++i) {
        const auto& o = observations[static_cast<std::size_t>(i)];
        X.row(i) = monomials((o.t - model.t_centre) / model.t_scale,
                             (o.z - model.z_centre) / model.z_scale);
        d[i] = o.d;
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
    qr.setThreshold(kRankThreshold);
    if (qr.rank() < kTerms) {
        model.undefined_reason =
            "the (t, z) points carry only " + std::to_string(qr.rank()) + " of the " +
            std::to_string(kTerms) +
            " terms (all at one t or one z, on one line, or fewer than 4 distinct values)";
        return model;
    }

    // The spread of d sets ε and the convergence tolerance in d's units.
    const MedianAndMad centre = median_and_mad(std::vector<double>(d.data(), d.data() + rows));
    const double spread = (d.array() - centre.median).abs().maxCoeff();
    const double epsilon = parameters.epsilon * (spread > 0 ? spread : 1.0);
    const double tolerance = parameters.tolerance * (spread > 0 ? spread : 1.0);

    ModelCoefficients a = qr.solve(d);  // ordinary least squares start
    Eigen::VectorXd r = d - X * a;
    ModelCoefficients best = a;
    double best_objective = r.lpNorm<1>();
    Eigen::MatrixXd weighted_X(rows, kTerms);
    Eigen::VectorXd weighted_d(rows);
    for (std::size_t iteration = 1; iteration <= parameters.max_iterations; ++iteration) {
        // Schlossmacher 1973: minimise Σ w_i r_i² with w_i = 1 / max(|r_i|, ε) from the
        // previous residuals; its fixed point minimises Σ |r_i|. Rows scaled by √w_i.
        const Eigen::VectorXd sqrt_w = r.cwiseAbs().cwiseMax(epsilon).cwiseInverse().cwiseSqrt();
        weighted_X = sqrt_w.asDiagonal() * X;
        weighted_d = sqrt_w.cwiseProduct(d);
        const ModelCoefficients next = weighted_X.colPivHouseholderQr().solve(weighted_d);
        if (!next.allFinite()) break;  // keep the best finite iterate
        const double step = (next - a).cwiseAbs().maxCoeff();
        a = next;
        r = d - X * a;
        model.iterations = iteration;
        const double objective = r.lpNorm<1>();
        if (objective < best_objective) best_objective = objective, best = a;
        if (step <= tolerance) {
            model.converged = true;
            break;
        }
    }
    model.coefficients = best;
    model.residuals = d - X * best;
    model.sum_abs_residuals = model.residuals.lpNorm<1>();
    const MedianAndMad spread_r =
        median_and_mad(std::vector<double>(model.residuals.data(), model.residuals.data() + rows));
    model.residual_scale = kMadToSigma * spread_r.mad;
    return model;
}

}  // namespace tlsmon::keypoints
