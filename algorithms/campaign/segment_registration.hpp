#pragma once
// Segment-wise ICP of a campaign cloud on the TLS reference (Blaskow & Maas, segment-based
// analysis: each segment fine-registered on its own, its transformation parameters compared
// with the other segments'), with what the study left out: each segment's parameters get a
// covariance, and a segment's surfaces that do not hold a direction say so instead of
// returning a number there.
//
// Parameters of a segment with centroid c (of its points before the fit):
//     x' = exp([θ]×)·(x − c) + c + t,
// so t is the displacement of the segment's centroid and θ its rotation about it — the
// quantities a segment far from the origin can be compared by.
//
// Metric: point-to-plane (Chen & Medioni 1992) to the local least-squares plane at the
// nearest reference point q (local_plane.hpp), not to the tangent plane through q: the
// nearest q is the one whose own noise best matches the point's, so n·(x' − q) understates
// the error and s0 with it (on a reference with 2 mm noise the χ² of the error was 1.3× its
// dof); the local plane averages q's noise away. or point-to-point as the study (Besl & McKay 1992;
// r = x' − q). Pairs farther than `outlier_k` robust σ (1.4826·MAD) from their counterpart are left
// out at each iteration.
//
// Degeneracy (Zhang, Kaess & Singh 2016, "On degeneracy of optimization-based state
// estimation problems"): the point-to-plane normal matrix N = Σ a·aᵀ (a = [(y × n); n], y =
// R·(x − c)), with the rotations scaled by the segment's radius L (rad → m at its rim), is
// the surfaces' information on each direction whatever the metric. Its eigenvectors whose
// eigenvalue is below `min_information` × the largest are not observed: a vertical face does
// not hold a shift along itself, a pier's faces not one along the pier. The Gauss–Newton steps
// are taken in the observed eigenvectors' span only (the study's point-to-point ICP would
// drift there along the sampling pattern), and the covariance is that of the observed
// combinations z = Uᵀ·D·p (D = diag(L, L, L, 1, 1, 1)), which is what a test may use.
//
// Covariance of z: the larger, in the matrix sense, of s0²·(UᵀÑU)⁻¹ for independent residuals
// and the cluster-robust sandwich over cells of `cluster_size` (Liang & Zeger 1986, with the
// small-sample factor of Cameron & Miller 2015) — a personal scanner's errors are correlated
// along its trajectory, so neighbouring points err alike.
#include <Eigen/Core>
#include <cstddef>
#include <span>

#include "algorithms/campaign/reference_surface.hpp"

namespace tlsmon::campaign {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

enum class IcpMetric { point_to_plane, point_to_point };
const char* metric_name(IcpMetric metric);

struct SegmentIcpParameters {
    IcpMetric metric = IcpMetric::point_to_plane;
    int max_iterations = 50;
    double tolerance = 1e-7;  // m: a step this small (at the segment's rim) ends the iteration
    double min_information = 0.01;  // of the strongest direction's, for a direction to count
    double outlier_k = 3.5;
    double cluster_size = 0.5;  // m
    int min_pairs = 50;
};

// unobserved: no pair lies on a surface a local plane models (a segment of vegetation or of
// small round parts), so no direction can be said to be observed — or, as the campaign
// comparison decides (min_planar_share), too few of them for the fit to stand for the segment.
enum class SegmentOutcome { registered, few_pairs, unobserved, diverged };
const char* outcome_name(SegmentOutcome outcome);

struct SegmentTransform {
    SegmentOutcome outcome = SegmentOutcome::few_pairs;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // c, m
    double radius = 0;                                   // L, m: RMS distance from c
    Vector6 parameters = Vector6::Zero();                // (θ rad, t m); 0 where not observed
    // The observed combinations z = observed·p (rows: unit eigenvectors of the scaled
    // information, times D) and their covariance (m², as the rotations are scaled by L).
    Eigen::Matrix<double, Eigen::Dynamic, 6> observed;
    Eigen::MatrixXd observed_covariance;
    Matrix6 covariance = Matrix6::Zero();  // of p, zero along what is not observed
    std::size_t points = 0, pairs = 0, outliers = 0, clusters = 0;
    std::size_t planar_pairs = 0;  // pairs whose reference plane models the surface
    double rmse = 0;               // m: of the residuals (distance to the plane or to the point)
    double sigma0 = 0;             // m: √(Σ r²/(m − rank))
    int iterations = 0;
    bool converged = false;
    int rank() const { return int(observed.rows()); }
    bool registered() const { return outcome == SegmentOutcome::registered; }
    // Whether parameter k (0–2 the rotations about x, y, z; 3–5 the translations) is
    // observed: its unit direction (in the scaled parameters) lies in the observed span, to 1 %
    // of its length.
    bool parameter_observed(int k) const;
    bool translation_observed(int axis) const { return parameter_observed(3 + axis); }
    Eigen::Matrix4d matrix() const;  // x' = M·x
    // Adds `variance` (m²) to each translation, in the observed combinations and in
    // `covariance`: a systematic error of that size in any direction (cut_bias.hpp).
    void add_translation_variance(double variance);
};

// The segment's parameters (as SegmentTransform::parameters) of a rigid transformation M of
// the whole cloud: θ = log(R), t = R·c + t_M − c.
Vector6 parameters_of(const Eigen::Matrix4d& transformation, const Eigen::Vector3d& centroid);

// Registers the segment's points (already in the reference frame after the global
// registration) on the reference surface. The result does not depend on `threads` (0: every
// core).
SegmentTransform register_segment(const ReferenceSurface& reference,
                                  std::span<const Eigen::Vector3d> segment,
                                  const SegmentIcpParameters& parameters = {},
                                  unsigned threads = 0);

void validate(const SegmentIcpParameters& parameters);

}  // namespace tlsmon::campaign
