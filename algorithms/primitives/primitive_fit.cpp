#include "algorithms/primitives/primitive_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/parallel_for.hpp"

namespace tlsmon::primitives {

namespace {

constexpr std::size_t kBlock = 1 << 15;  // points per block of the sums (fixed: deterministic)

// σ_n of a point along the surface normal n (header).
double normal_sigma(const ScannerNoise& noise, const Eigen::Vector3d& p,
                    const Eigen::Vector3d& scanner, const Eigen::Vector3d& n, double& cos_i) {
    const Eigen::Vector3d beam = p - scanner;
    const double range = beam.norm();
    cos_i = range > 0.0 ? std::abs(n.dot(beam) / range) : 1.0;
    const double sr = noise.range_sigma(range), sa = range * noise.angular_sigma();
    return std::sqrt(sr * sr * cos_i * cos_i + sa * sa * (1.0 - cos_i * cos_i));
}

// The points within the band of `prim`, seen within the incidence limit.
std::vector<std::uint32_t> candidates_of(std::span<const Eigen::Vector3d> points,
                                         const Eigen::Vector3d& scanner, const Primitive& prim,
                                         const FitParameters& params, const ScannerNoise& noise) {
    const double min_cos = std::cos(params.max_incidence_deg * std::numbers::pi / 180.0);
    const std::size_t blocks = (points.size() + kBlock - 1) / kBlock;
    std::vector<std::vector<std::uint32_t>> kept(blocks);
    parallel_for(
        blocks,
        [&](std::size_t b) {
            Eigen::VectorXd g(parameter_count(prim.kind));
            const std::size_t end = std::min(points.size(), (b + 1) * kBlock);
            for (std::size_t i = b * kBlock; i < end; ++i) {
                if (std::abs(prim.distance(points[i], g)) > params.band) continue;
                double cos_i = 1.0;
                normal_sigma(noise, points[i], scanner, prim.normal_at(points[i]), cos_i);
                if (cos_i >= min_cos) kept[b].push_back(static_cast<std::uint32_t>(i));
            }
        },
        params.threads);
    std::vector<std::uint32_t> out;
    for (auto& k : kept) out.insert(out.end(), k.begin(), k.end());
    return out;
}

struct Sums {
    Eigen::MatrixXd N;
    Eigen::VectorXd rhs;
    double omega = 0.0, squares = 0.0;
    std::size_t used = 0;
};

// The normal equations over the candidates whose normalised distance stays within `limit`.
Sums normal_equations(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& scanner,
                      const ScannerNoise& noise, const Primitive& prim,
                      const std::vector<std::uint32_t>& candidates, double limit,
                      std::vector<double>* normalised, unsigned threads) {
    const int u = parameter_count(prim.kind);
    const std::size_t blocks = (candidates.size() + kBlock - 1) / kBlock;
    std::vector<Sums> partial(blocks);
    if (normalised) normalised->assign(candidates.size(), 0.0);
    parallel_for(
        blocks,
        [&](std::size_t b) {
            Sums& s = partial[b];
            s.N = Eigen::MatrixXd::Zero(u, u);
            s.rhs = Eigen::VectorXd::Zero(u);
            Eigen::VectorXd g(u);
            const std::size_t end = std::min(candidates.size(), (b + 1) * kBlock);
            for (std::size_t k = b * kBlock; k < end; ++k) {
                const Eigen::Vector3d& p = points[candidates[k]];
                const double d = prim.distance(p, g);
                double cos_i = 1.0;
                const double sigma = normal_sigma(noise, p, scanner, prim.normal_at(p), cos_i);
                const double w = d / sigma;
                if (normalised) (*normalised)[k] = std::abs(w);
                if (std::abs(w) > limit) continue;
                const double weight = 1.0 / (sigma * sigma);
                s.N.selfadjointView<Eigen::Lower>().rankUpdate(g, weight);
                s.rhs -= weight * d * g;
                s.omega += w * w;
                s.squares += d * d;
                ++s.used;
            }
        },
        threads);
    Sums total;
    total.N = Eigen::MatrixXd::Zero(u, u);
    total.rhs = Eigen::VectorXd::Zero(u);
    for (const Sums& s : partial) {
        total.N += s.N;
        total.rhs += s.rhs;
        total.omega += s.omega;
        total.squares += s.squares;
        total.used += s.used;
    }
    total.N = total.N.selfadjointView<Eigen::Lower>();
    return total;
}

// The clipping limit: k times the robust scale of the normalised distances (1.4826·median
// |w|), never below the stochastic model's own (1).
double clip_limit(std::vector<double> normalised, double k) {
    if (normalised.empty()) return k;
    auto mid = normalised.begin() + std::ptrdiff_t(normalised.size() / 2);
    std::nth_element(normalised.begin(), mid, normalised.end());
    return k * std::max(1.0, 1.4826 * *mid);
}

}  // namespace

const char* to_string(FitStatus status) {
    switch (status) {
        case FitStatus::fitted:
            return "fitted";
        case FitStatus::too_few_points:
            return "too few points";
        case FitStatus::not_converged:
            return "not converged";
        case FitStatus::singular:
            return "singular (the points do not fix every parameter)";
    }
    return "?";
}

Fit fit_primitive(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& scanner,
                  const ScannerNoise& noise, const Primitive& start, const FitParameters& params) {
    Fit fit;
    fit.primitive = start;
    const int u = parameter_count(start.kind);
    // Two rounds: the candidates from the start, then again from the first round's fit (a
    // coarse start's band and incidence are off by its own error).
    for (int round = 0; round < 2; ++round) {
        const auto candidates = candidates_of(points, scanner, fit.primitive, params, noise);
        fit.candidates = candidates.size();
        if (candidates.size() < std::max<std::size_t>(params.min_points, std::size_t(u) + 1)) {
            fit.status = FitStatus::too_few_points;
            return fit;
        }
        fit.status = FitStatus::not_converged;
        std::vector<double> normalised;
        for (int it = 0; it < params.max_iterations; ++it) {
            ++fit.iterations;
            normal_equations(points, scanner, noise, fit.primitive, candidates,
                             std::numeric_limits<double>::infinity(), &normalised, params.threads);
            const double limit = clip_limit(normalised, params.clip_k);
            const Sums s = normal_equations(points, scanner, noise, fit.primitive, candidates,
                                            limit, nullptr, params.threads);
            const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.N);
            if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) {
                fit.status = FitStatus::singular;
                return fit;
            }
            const Eigen::VectorXd step = ldlt.solve(s.rhs);
            fit.primitive.x += step;
            if (step.norm() < 1e-9 * std::max(1.0, fit.primitive.x.norm())) {
                fit.status = FitStatus::fitted;
                break;
            }
        }
        if (fit.status != FitStatus::fitted) return fit;
    }
    // The final sums at the solution: Ω, the covariance.
    const auto candidates = candidates_of(points, scanner, fit.primitive, params, noise);
    std::vector<double> normalised;
    normal_equations(points, scanner, noise, fit.primitive, candidates,
                     std::numeric_limits<double>::infinity(), &normalised, params.threads);
    const Sums s = normal_equations(points, scanner, noise, fit.primitive, candidates,
                                    clip_limit(normalised, params.clip_k), nullptr, params.threads);
    fit.candidates = candidates.size();
    fit.used = s.used;
    if (s.used <= std::size_t(u)) {
        fit.status = FitStatus::too_few_points;
        return fit;
    }
    const double s0_squared = s.omega / double(s.used - std::size_t(u));
    fit.s0 = std::sqrt(s0_squared);
    fit.rms = std::sqrt(s.squares / double(s.used));
    fit.covariance = std::max(1.0, s0_squared) * s.N.inverse();
    return fit;
}

}  // namespace tlsmon::primitives
