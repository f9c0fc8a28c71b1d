#include "algorithms/campaign/segment_consistency.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/so3.hpp"

namespace tlsmon::campaign {

namespace {

// p = A(c − o)·q to first order in θ (the header's model).
Matrix6 common_to_segment(const Eigen::Vector3d& arm) {
    Matrix6 A = Matrix6::Identity();
    A.bottomLeftCorner<3, 3>() = -registration::skew(arm);  // θ × arm = −[arm]×·θ
    return A;
}

struct Term {
    Eigen::MatrixXd BA;       // rank × 6
    Eigen::MatrixXd S, Sinv;  // rank × rank
    Eigen::VectorXd z;
    Matrix6 M;  // (BA)ᵀ S⁻¹ BA
    Vector6 g;  // (BA)ᵀ S⁻¹ z
};

// Rank of a symmetric matrix by its eigenvalues relative to the largest.
int rank_of(const Matrix6& M) {
    const Eigen::SelfAdjointEigenSolver<Matrix6> es(M);
    const double top = es.eigenvalues()(5);
    int r = 0;
    for (int k = 0; k < 6; ++k) r += es.eigenvalues()(k) > 1e-9 * top;
    return top > 0 ? r : 0;
}

}  // namespace

SegmentConsistency test_segment_consistency(std::span<const SegmentTransform> segments,
                                            double alpha) {
    SegmentConsistency out;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.segment_statistic.assign(segments.size(), nan);
    out.segment_dof.assign(segments.size(), 0);
    out.segment_p_value.assign(segments.size(), nan);
    std::vector<std::size_t> used;
    for (std::size_t i = 0; i < segments.size(); ++i)
        if (segments[i].registered() && segments[i].rank() > 0) {
            used.push_back(i);
            out.origin += segments[i].centroid;
        }
    out.segments = used.size();
    if (used.size() < 2) return out;
    out.origin /= double(used.size());

    std::vector<Term> terms;
    Matrix6 M = Matrix6::Zero();
    Vector6 g = Vector6::Zero();
    int observations = 0;
    for (const std::size_t i : used) {
        const SegmentTransform& s = segments[i];
        Term term;
        term.BA = s.observed * common_to_segment(s.centroid - out.origin);
        term.S = s.observed_covariance;
        term.Sinv = term.S.ldlt().solve(Eigen::MatrixXd::Identity(s.rank(), s.rank()));
        term.z = s.observed * s.parameters;
        term.M = term.BA.transpose() * term.Sinv * term.BA;
        term.g = term.BA.transpose() * term.Sinv * term.z;
        M += term.M;
        g += term.g;
        observations += s.rank();
        terms.push_back(std::move(term));
    }
    if (rank_of(M) < 6) return out;  // the segments together do not hold every direction
    const Eigen::LDLT<Matrix6> ldlt(M);
    out.common = ldlt.solve(g);
    out.common_covariance = ldlt.solve(Matrix6::Identity());
    for (const Term& term : terms) {
        const Eigen::VectorXd e = term.z - term.BA * out.common;
        out.statistic += e.dot(term.Sinv * e);
    }
    out.dof = observations - 6;
    if (out.dof > 0) {
        out.p_value = registration::chi_square_upper_tail(out.statistic, out.dof);
        out.differ = out.statistic > registration::chi_square_quantile(1 - alpha, out.dof);
    }
    // Each segment against the common transformation of the others.
    for (std::size_t k = 0; k < used.size(); ++k) {
        const Term& term = terms[k];
        const Matrix6 Mo = M - term.M;
        if (rank_of(Mo) < 6) continue;
        const Eigen::LDLT<Matrix6> lo(Mo);
        const Vector6 q = lo.solve(g - term.g);
        const Eigen::VectorXd d = term.z - term.BA * q;
        const Eigen::MatrixXd S = term.S + term.BA * lo.solve(term.BA.transpose());
        const double T = d.dot(S.ldlt().solve(d));
        const std::size_t i = used[k];
        out.segment_statistic[i] = T;
        out.segment_dof[i] = int(d.size());
        out.segment_p_value[i] = registration::chi_square_upper_tail(T, double(d.size()));
    }
    return out;
}

}  // namespace tlsmon::campaign
