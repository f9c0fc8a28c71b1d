#pragma once
// Whether a campaign cloud's segments moved as one body: the test the segment-based study
// (Blaskow & Maas) did not make — it looked at the segments' parameters. H0: every segment's
// parameters are those of one common rigid transformation q of the whole cloud (about the
// origin o, the mean of the centroids), i.e. for the segment with centroid c, to first order
//     θ = θ_q,   t = t_q + θ_q × (c − o),          p = A(c)·q
// observed through each segment's observed combinations z = B·p (segment_registration.hpp)
// with covariance S. The common q by generalised least squares, M = Σ AᵀBᵀS⁻¹BA; then
//     T = Σ (z − BAq̂)ᵀ S⁻¹ (z − BAq̂) ~ χ²(Σ rank − rank M)
// (the global test of the adjustment; Niemeier 2008 §4.5). Each segment is also tested
// against the others' common transformation (leave one out): d = z − BAq̂₍₋ᵢ₎,
// dᵀ(S + BA·M₍₋ᵢ₎⁻¹·AᵀBᵀ)⁻¹d ~ χ²(rank) — a segment of its own, as a drifted stretch of the
// trajectory.
#include <Eigen/Core>
#include <span>
#include <vector>

#include "algorithms/campaign/segment_registration.hpp"

namespace tlsmon::campaign {

struct SegmentConsistency {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // o, m
    Vector6 common = Vector6::Zero();                  // q̂ = (θ rad, t m) about o
    Matrix6 common_covariance = Matrix6::Zero();
    double statistic = 0;  // T
    int dof = 0;
    double p_value = 1;
    bool differ = false;  // T beyond the χ² quantile 1 − α
    // Per segment (NaN/0 for a segment not registered, or when the others do not determine q).
    std::vector<double> segment_statistic;
    std::vector<int> segment_dof;
    std::vector<double> segment_p_value;
    std::size_t segments = 0;  // registered segments in the test
};

// Segments not registered are left out; fewer than two, or combined observations that do
// not determine the common transformation, give dof 0 and no verdict.
SegmentConsistency test_segment_consistency(std::span<const SegmentTransform> segments,
                                            double alpha = 0.05);

}  // namespace tlsmon::campaign
