#include "algorithms/registration/plane_matching_without_prior.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/registration/plane_matching.hpp"
#include "algorithms/registration/plane_registration.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {

namespace {

double wrapped(double a) {
    return std::remainder(a, 2.0 * std::numbers::pi);
}

// κ_re of every pair of planes with equal elevation and a horizontal part (step 1).
std::vector<double> heading_votes(std::span<const FittedPlane> reference,
                                  std::span<const FittedPlane> epoch,
                                  const PriorFreeMatchingParams& p) {
    const double elevation = std::sin(p.max_angle_deg * std::numbers::pi / 180.0);
    std::vector<double> votes;
    for (const auto& r : reference) {
        if (r.normal.head<2>().norm() < p.min_horizontal) continue;
        for (const auto& e : epoch) {
            if (e.normal.head<2>().norm() < p.min_horizontal) continue;
            if (std::fabs(r.normal.z() - e.normal.z()) > elevation) continue;
            votes.push_back(wrapped(std::atan2(r.normal.y(), r.normal.x()) -
                                    std::atan2(e.normal.y(), e.normal.x())));
        }
    }
    return votes;
}

// The strongest peaks of the votes: each vote's count of votes within the tolerance, the
// peak's heading their mean; peaks closer than twice the tolerance are one.
std::vector<std::pair<double, int>> heading_peaks(const std::vector<double>& votes,
                                                  const PriorFreeMatchingParams& p) {
    const double tol = p.max_angle_deg * std::numbers::pi / 180.0;
    std::vector<std::pair<double, int>> scored;  // (mean heading, count)
    for (const double v : votes) {
        double sum = 0;
        int n = 0;
        for (const double w : votes) {
            const double d = wrapped(w - v);
            if (std::fabs(d) <= tol) {
                sum += d;
                ++n;
            }
        }
        scored.emplace_back(wrapped(v + sum / n), n);
    }
    std::sort(scored.begin(), scored.end(),
              [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<std::pair<double, int>> peaks;
    for (const auto& s : scored) {
        if (int(peaks.size()) == p.heading_peaks) break;
        const bool near = std::any_of(peaks.begin(), peaks.end(), [&](const auto& q) {
            return std::fabs(wrapped(q.first - s.first)) < 2.0 * tol;
        });
        if (!near) peaks.push_back(s);
    }
    return peaks;
}

struct Pair {
    std::size_t reference, epoch;
};

// The pairs that one (R, t) explains, one per reference plane (the smallest offset) and one
// per epoch plane (of `distinct`: with either_sign, plane j and j + distinct are one plane).
std::vector<Pair> explained(std::span<const FittedPlane> reference,
                            std::span<const FittedPlane> epoch, std::size_t distinct,
                            const std::vector<Pair>& pairs, const Eigen::Matrix3d& R,
                            const Eigen::Vector3d& t, const PriorFreeMatchingParams& p) {
    std::vector<double> best(reference.size(), p.max_offset);
    std::vector<std::optional<std::size_t>> chosen(reference.size());
    for (const auto& [i, j] : pairs) {
        const FittedPlane& r = reference[i];
        const FittedPlane& e = epoch[j];
        const Eigen::Vector3d d = R * e.centroid + t - r.centroid;
        const double offset = std::fabs(r.normal.dot(d));
        if (offset > best[i]) continue;
        const double reach = p.overlap_factor * (std::hypot(r.extent_long, r.extent_short) +
                                                 std::hypot(e.extent_long, e.extent_short));
        if ((d - r.normal.dot(d) * r.normal).norm() > reach) continue;
        best[i] = offset;
        chosen[i] = j;
    }
    std::vector<Pair> out;
    std::vector<bool> epoch_taken(distinct);
    for (std::size_t i = 0; i < reference.size(); ++i) {
        if (!chosen[i] || epoch_taken[*chosen[i] % distinct]) continue;
        epoch_taken[*chosen[i] % distinct] = true;
        out.push_back({i, *chosen[i]});
    }
    return out;
}

struct Hypothesis {
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    std::vector<Pair> support;
};

// Step 2 for one heading: translations from three pairs with well-spread normals.
Hypothesis best_translation(std::span<const FittedPlane> reference,
                            std::span<const FittedPlane> epoch, std::size_t distinct,
                            const Eigen::Matrix3d& R, const PriorFreeMatchingParams& p,
                            std::mt19937& rng) {
    const double cos_max = std::cos(p.max_angle_deg * std::numbers::pi / 180.0);
    std::vector<Pair> pairs;
    for (std::size_t i = 0; i < reference.size(); ++i) {
        for (std::size_t j = 0; j < epoch.size(); ++j) {
            if ((R * epoch[j].normal).dot(reference[i].normal) >= cos_max) pairs.push_back({i, j});
        }
    }
    Hypothesis best;
    if (pairs.size() < 3) return best;
    std::uniform_int_distribution<std::size_t> pick(0, pairs.size() - 1);
    for (int k = 0; k < p.hypotheses; ++k) {
        const Pair a = pairs[pick(rng)], b = pairs[pick(rng)], c = pairs[pick(rng)];
        Eigen::Matrix3d N;
        Eigen::Vector3d rhs;
        int row = 0;
        for (const Pair& q : {a, b, c}) {
            const FittedPlane& r = reference[q.reference];
            N.row(row) = r.normal.transpose();
            rhs(row++) = r.normal.dot(r.centroid - R * epoch[q.epoch].centroid);
        }
        // |det| of three unit normals: 1 for orthogonal ones, 0 for coplanar directions.
        if (std::fabs(N.determinant()) < 0.2) continue;
        const Eigen::Vector3d t = N.partialPivLu().solve(rhs);
        auto support = explained(reference, epoch, distinct, pairs, R, t, p);
        if (support.size() > best.support.size()) best = {t, std::move(support)};
    }
    return best;
}

}  // namespace

std::optional<PriorFreeMatch> match_planes_without_prior(std::span<const FittedPlane> reference,
                                                         std::span<const FittedPlane> epoch,
                                                         const PriorFreeMatchingParams& params) {
    reference = reference.first(std::min(reference.size(), params.max_planes));
    epoch = epoch.first(std::min(epoch.size(), params.max_planes));
    const std::size_t distinct = epoch.size();
    std::vector<FittedPlane> either;  // each plane, then each with its opposite normal
    if (params.either_sign) {
        either.assign(epoch.begin(), epoch.end());
        for (std::size_t j = 0; j < distinct; ++j) {
            either.push_back(epoch[j]);
            either.back().normal = -epoch[j].normal;
        }
        epoch = either;
    }
    std::mt19937 rng(1);
    std::optional<PriorFreeMatch> out;
    std::vector<Pair> winner;
    // With either_sign every heading's opposite has the same votes: twice the peaks are tried.
    PriorFreeMatchingParams peaks = params;
    if (params.either_sign) peaks.heading_peaks *= 2;
    for (const auto& [kappa, votes] :
         heading_peaks(heading_votes(reference, epoch, params), peaks)) {
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(kappa, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        Hypothesis h = best_translation(reference, epoch, distinct, R, params, rng);
        if (out && h.support.size() <= out->support) {
            out->runner_up = std::max(out->runner_up, h.support.size());
            continue;
        }
        PriorFreeMatch m;
        m.approximate.rotation = R;
        m.approximate.translation = h.translation;
        m.heading = kappa;
        m.support = h.support.size();
        if (out) m.runner_up = out->support;
        out = m;
        winner = std::move(h.support);
    }
    if (!out || out->support < params.min_support) return std::nullopt;
    // Step 3: the six parameters on the winner's pairs.
    std::vector<PlaneCorrespondence> pairs;
    for (const auto& [i, j] : winner) pairs.push_back({reference[i], epoch[j]});
    try {
        RigidTransform adjusted = adjust_planes(pairs, {}, out->approximate).transform;
        out->approximate = std::move(adjusted);
    } catch (const Error&) {
        return std::nullopt;  // the supporting normals do not span space
    }
    return out;
}

}  // namespace tlsmon::registration
