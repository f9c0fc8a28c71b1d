#include "algorithms/campaign/segment_registration.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "algorithms/cell_key.hpp"
#include "algorithms/registration/point_to_plane.hpp"
#include "algorithms/registration/so3.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"
#include "core/statistics.hpp"

namespace tlsmon::campaign {

const char* metric_name(IcpMetric metric) {
    return metric == IcpMetric::point_to_point ? "point-to-point" : "point-to-plane";
}

const char* outcome_name(SegmentOutcome outcome) {
    switch (outcome) {
        case SegmentOutcome::registered:
            return "registered";
        case SegmentOutcome::few_pairs:
            return "few pairs";
        case SegmentOutcome::unobserved:
            return "unobserved";
        case SegmentOutcome::diverged:
            break;
    }
    return "diverged";
}

void validate(const SegmentIcpParameters& p) {
    if (p.max_iterations < 1) throw Error("campaign: max_iterations must be at least 1");
    if (!(p.tolerance > 0)) throw Error("campaign: tolerance must be positive");
    if (!(p.min_information > 0 && p.min_information < 1))
        throw Error("campaign: min_information must lie in (0, 1)");
    if (!(p.outlier_k > 1)) throw Error("campaign: outlier_k must exceed 1");
    if (!(p.cluster_size > 0)) throw Error("campaign: cluster_size must be positive");
    if (p.min_pairs < 7) throw Error("campaign: min_pairs must be at least 7");
}

bool SegmentTransform::parameter_observed(int k) const {
    // Column k of Uᵀ·D is D_k times the unit direction's components in the observed span.
    const double scale = k < 3 ? radius : 1.0;
    return observed.rows() > 0 && observed.col(k).squaredNorm() / (scale * scale) >= 0.99;
}

using registration::exp_so3;
using registration::log_so3;

Eigen::Matrix4d SegmentTransform::matrix() const {
    const Eigen::Matrix3d R = exp_so3(parameters.head<3>());
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    M.topLeftCorner<3, 3>() = R;
    M.topRightCorner<3, 1>() = centroid + parameters.tail<3>() - R * centroid;
    return M;
}

Vector6 parameters_of(const Eigen::Matrix4d& M, const Eigen::Vector3d& c) {
    const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
    Vector6 p;
    p.head<3>() = log_so3(R);
    p.tail<3>() = R * c + M.topRightCorner<3, 1>() - c;
    return p;
}

namespace {

// The cell of a pair for the cluster-robust covariance: that of its reference point projected
// onto the local plane. Not the point itself: a surface lying on a cell boundary (a floor at
// z = 0) would split its points between two cells by the sign of their noise, and the cells'
// mean residuals would carry that sign — correlation made by the cells, not by the scan.
std::uint64_t cell_of(const ReferenceSurface& ref, std::int64_t q, double size) {
    const LocalPlane& plane = ref.plane(q);
    return cell_key(ref.point(q) - plane.distance(ref.point(q)) * plane.normal.cast<double>(),
                    size);
}

// One segment point paired with its nearest reference point.
struct Pair {
    Eigen::Vector3d y;       // R·(x − c)
    Eigen::Vector3d moved;   // y + c + t
    std::int64_t reference;  // index
    bool planar;             // the reference's local plane models the surface there
};

using Rows = Eigen::Matrix<double, 3, 6>;

// The pair's design rows in the scaled parameters s = D·p (one row point-to-plane, the others
// zero; three point-to-point) and its residuals; returns the number of rows.
int design(const Pair& pr, const ReferenceSurface& ref, IcpMetric metric, double L, Rows& A,
           Eigen::Vector3d& r) {
    const Eigen::Vector3d& y = pr.y;
    if (metric == IcpMetric::point_to_plane) {
        A.setZero();
        r.setZero();
        const LocalPlane& plane = ref.plane(pr.reference);
        const Eigen::Vector3d n = plane.normal.cast<double>();
        A.row(0).head<3>() = y.cross(n).transpose() / L;
        A.row(0).tail<3>() = n.transpose();
        r(0) = plane.distance(pr.moved);
        return 1;
    }
    // ∂(exp([δθ]×)·y)/∂δθ = −[y]× (so3.hpp).
    A.leftCols<3>() = -registration::skew(y) / L;
    A.rightCols<3>().setIdentity();
    r = pr.moved - ref.point(pr.reference);
    return 3;
}

double residual_size(const Pair& pr, const ReferenceSurface& ref, IcpMetric metric) {
    return metric == IcpMetric::point_to_plane
               ? std::abs(ref.plane(pr.reference).distance(pr.moved))
               : (pr.moved - ref.point(pr.reference)).norm();
}

}  // namespace

void SegmentTransform::add_translation_variance(double variance) {
    if (!registered() || !(variance > 0)) return;
    // z = observed·p, so Cov(z) gains observed_t·(v·I)·observed_tᵀ; p's covariance in the
    // observed span is Ds·Cov(z)·Dsᵀ with Ds = D⁻¹·U and U = (observed·D⁻¹)ᵀ.
    const Eigen::MatrixXd added =
        variance * observed.rightCols<3>() * observed.rightCols<3>().transpose();
    observed_covariance += added;
    Matrix6 Dinv = Matrix6::Identity();
    Dinv.diagonal().head<3>().setConstant(1.0 / radius);
    const Eigen::Matrix<double, 6, Eigen::Dynamic> Ds = Dinv * (observed * Dinv).transpose();
    covariance += Ds * added * Ds.transpose();
}

SegmentTransform register_segment(const ReferenceSurface& ref,
                                  std::span<const Eigen::Vector3d> segment,
                                  const SegmentIcpParameters& P, unsigned threads) {
    validate(P);
    SegmentTransform out;
    std::vector<Eigen::Vector3d> points;
    points.reserve(segment.size());
    for (const auto& x : segment)
        if (x.allFinite()) points.push_back(x);
    out.points = points.size();
    if (points.size() < std::size_t(P.min_pairs)) return out;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& x : points) c += x;
    c /= double(points.size());
    double spread = 0;
    for (const auto& x : points) spread += (x - c).squaredNorm();
    const double L = std::max(1e-3, std::sqrt(spread / double(points.size())));
    out.centroid = c;
    out.radius = L;

    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    std::vector<Pair> pairs;
    std::vector<double> sizes;
    bool last = false;  // the pass after convergence, for the covariance
    for (int it = 0;; ++it) {
        // Pairs: every point's nearest reference point (in parallel: the searches are the
        // cost), then the robust cut.
        pairs.resize(points.size());
        parallel_for(
            points.size(),
            [&](std::size_t i) {
                Pair& pr = pairs[i];
                pr.y = R * (points[i] - c);
                pr.moved = pr.y + c + t;
                pr.reference = ref.nearest(pr.moved);
                pr.planar = pr.reference >= 0 && ref.planar(pr.reference);
            },
            threads);
        // Point-to-plane needs the plane; point-to-point pairs any point, and only the planar
        // ones tell what the surfaces hold.
        std::erase_if(pairs, [&](const Pair& pr) {
            return pr.reference < 0 || (!pr.planar && P.metric == IcpMetric::point_to_plane);
        });
        sizes.clear();
        for (const auto& pr : pairs) sizes.push_back(residual_size(pr, ref, P.metric));
        const double scale = kMadToSigma * median_high(sizes);
        // A step below 10 % of the estimate's own precision (≈ σ/√n) ends the iteration: the
        // pairs of a noisy cloud flip back and forth below it.
        const double precision = scale / std::sqrt(double(std::max<std::size_t>(1, sizes.size())));
        const double cut = P.outlier_k * std::max(scale, 1e-9);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < pairs.size(); ++i)
            if (sizes[i] <= cut) pairs[kept++] = pairs[i];
        out.outliers = pairs.size() - kept;
        pairs.resize(kept);
        if (pairs.size() < std::size_t(P.min_pairs)) {
            out.outcome = SegmentOutcome::few_pairs;
            out.pairs = pairs.size();
            return out;
        }

        // The metric's normal equations and the surfaces' information (point-to-plane, scaled:
        // the point-to-plane metric's own N; point-to-point's planar pairs summed apart).
        Matrix6 N = Matrix6::Zero(), planes = Matrix6::Zero();
        Vector6 b = Vector6::Zero();
        for (const auto& pr : pairs) {
            Rows A;
            Eigen::Vector3d r;
            design(pr, ref, P.metric, L, A, r);
            N += A.transpose() * A;
            b += A.transpose() * r;
            if (P.metric == IcpMetric::point_to_point && pr.planar) {
                design(pr, ref, IcpMetric::point_to_plane, L, A, r);
                planes += A.row(0).transpose() * A.row(0);
            }
        }
        const Matrix6& information = P.metric == IcpMetric::point_to_plane ? N : planes;
        const Eigen::SelfAdjointEigenSolver<Matrix6> es(information);
        const double strongest = es.eigenvalues()(5);
        int rank = 0;
        while (rank < 6 && strongest > 0 &&
               es.eigenvalues()(5 - rank) >= P.min_information * strongest)
            ++rank;
        if (rank == 0) {  // no pair on a surface a plane models
            out.outcome = SegmentOutcome::unobserved;
            out.pairs = pairs.size();
            return out;
        }
        const Eigen::MatrixXd U = es.eigenvectors().rightCols(rank);  // observed, scaled space
        const Eigen::MatrixXd Nr = U.transpose() * N * U;
        const Eigen::LLT<Eigen::MatrixXd> llt(Nr);
        if (llt.info() != Eigen::Success) {
            out.outcome = SegmentOutcome::diverged;
            return out;
        }

        if (last || it >= P.max_iterations) {
            // Covariance of z = Uᵀ·s at the solution.
            const Eigen::MatrixXd Ninv = llt.solve(Eigen::MatrixXd::Identity(rank, rank));
            std::unordered_map<std::uint64_t, Eigen::VectorXd> cells;
            double rr = 0, rows = 0;
            for (const auto& pr : pairs) {
                Rows A;
                Eigen::Vector3d r;
                rows += design(pr, ref, P.metric, L, A, r);
                rr += r.squaredNorm();
                const Eigen::VectorXd g = U.transpose() * (A.transpose() * r);
                auto [cell, fresh] =
                    cells.try_emplace(cell_of(ref, pr.reference, P.cluster_size), g);
                if (!fresh) cell->second += g;
            }
            const double s02 = rr / std::max(1.0, rows - rank);
            Eigen::MatrixXd S = s02 * Ninv;
            const double C = double(cells.size());
            if (C >= 2) {
                Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(rank, rank);
                for (const auto& [key, g] : cells) meat += g * g.transpose();
                const double small_sample = C / (C - 1) * (rows - 1) / std::max(1.0, rows - rank);
                Eigen::MatrixXd sandwich = small_sample * Ninv * meat * Ninv;
                S = registration::larger_of(S, 0.5 * (sandwich + sandwich.transpose()));
            }
            Eigen::Matrix<double, 6, 6> D = Matrix6::Identity();
            D.diagonal().head<3>().setConstant(L);
            out.observed = U.transpose() * D;
            out.observed_covariance = S;
            const Eigen::MatrixXd Ds = D.inverse() * U;
            out.covariance = Ds * S * Ds.transpose();
            out.parameters.head<3>() = log_so3(R);
            out.parameters.tail<3>() = t;
            out.pairs = pairs.size();
            out.planar_pairs = std::size_t(std::count_if(pairs.begin(), pairs.end(),
                                                         [](const Pair& pr) { return pr.planar; }));
            out.clusters = cells.size();
            out.rmse = std::sqrt(rr / rows);
            out.sigma0 = std::sqrt(s02);
            out.iterations = it;
            out.converged = last;
            out.outcome = SegmentOutcome::registered;
            return out;
        }

        // A Gauss–Newton step: point-to-plane in the observed span only (solution remapping);
        // point-to-point, as the study's ICP, in every direction — its pairs hold them all,
        // by the sampling where the surfaces do not, so only the observed ones are reported.
        Vector6 ds;
        if (P.metric == IcpMetric::point_to_plane)
            ds = U * (-llt.solve(U.transpose() * b));
        else
            ds = -N.ldlt().solve(b);
        if (!ds.allFinite()) {
            out.outcome = SegmentOutcome::diverged;
            return out;
        }
        R = exp_so3(ds.head<3>() / L) * R;
        t += ds.tail<3>();
        // Farther than its pairs could ever have pulled it: lost, not registered.
        if (t.norm() > 4 * ref.parameters().max_distance) {
            out.outcome = SegmentOutcome::diverged;
            return out;
        }
        last = ds.norm() < std::max(P.tolerance, 0.1 * precision);
    }
}

}  // namespace tlsmon::campaign
