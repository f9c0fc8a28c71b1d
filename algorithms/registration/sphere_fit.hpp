#pragma once
// The centre of a sphere target from the scan points near its predicted position: a seeded
// RANSAC with the known radius rejects what is not the sphere (its mast, the ground, mixed
// pixels trailing behind the silhouette), least squares with the known radius gives the
// centre and its covariance, and a fit with a free radius checks that the points are the
// sphere they are meant to be. A TLS sees only the cap that faces it; the covariance says
// what that geometry supports.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>

namespace tlsmon::registration {

struct SphereFitParams {
    double radius = 0.0725;               // m, the target's known radius
    double max_centre_offset = 0.05;      // m, how far the centre may lie from the prediction
    double inlier_threshold = 0.004;      // m, |distance to the sphere| counted as consensus
    int ransac_iterations = 256;          // 3-point samples; 50 % inliers fail with p ≈ 1e-15
    std::uint64_t seed = 1;               // same points + same seed -> same result
    double outlier_k = 4.0;               // final inliers: |v| ≤ k·σ̂ (σ̂ = 1.4826·MAD)
    double min_noise = 0.0001;            // m, floor of σ̂ in that bound
    std::size_t min_points = 30;          // inliers needed for a centre
    double max_radius_deviation = 0.003;  // m, |free radius − known radius|
    double max_rms = 0.003;               // m, RMS distance of the inliers to the sphere
    double min_coverage = 0.02;           // λ_min of mean(u·uᵀ), u = unit vectors centre->point
    int max_iterations = 30;              // Gauss–Newton iterations per fit
    // Where the sphere is held (its stud, mast or pole): the unit direction from the centre, in
    // the points' frame (zero: nowhere). The points within mount_cap_deg of it are left out of
    // the final fit: there the mount meets the sphere, its points lie within the noise of the
    // sphere's surface, and how many of them a scan keeps changes with the grid's phase.
    Eigen::Vector3d mount = Eigen::Vector3d::Zero();
    double mount_cap_deg = 0.0;
};

enum class SphereFitStatus { found, not_found, bad_fit };

enum class SphereFitReason {
    none,
    too_few_points,              // not_found: fewer points near the prediction than min_points
    no_consensus,                // not_found: no sphere of that radius near the prediction
    too_few_inliers,             // not_found: the refined inlier set is below min_points
    centre_far_from_prediction,  // not_found: the fitted centre left the allowed offset
    not_converged,               // bad_fit: Gauss–Newton did not settle
    coverage_one_sided,          // bad_fit: the points cover too small or one-sided a cap
    radius_check_failed,         // bad_fit: the free radius deviates from the known one
    residual_rms_too_large,      // bad_fit: the points scatter more than max_rms
};

const char* describe(SphereFitReason reason);

struct SphereFit {
    SphereFitStatus status = SphereFitStatus::not_found;
    SphereFitReason reason = SphereFitReason::too_few_points;
    std::string detail;  // the numbers behind a reason other than `none`

    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    // Known-radius fit: the centre and its covariance (m²) from the residuals, robust to
    // points of unequal precision (see sphere_fit.cpp); the classical s0²·N⁻¹ beside it.
    Eigen::Vector3d centre = Eigen::Vector3d::Constant(nan);
    Eigen::Matrix3d centre_covariance = Eigen::Matrix3d::Constant(nan);
    Eigen::Matrix3d centre_covariance_homoscedastic = Eigen::Matrix3d::Constant(nan);
    double sigma0 = nan;      // m, a posteriori σ of one point's distance to the sphere
    double rms = nan;         // m, RMS of the inliers' distances to the sphere
    std::size_t points = 0;   // points given
    std::size_t inliers = 0;  // points used by the final fit
    int iterations = 0;

    // Free-radius fit on the same inliers: the check.
    Eigen::Vector3d free_centre = Eigen::Vector3d::Constant(nan);
    double free_radius = nan;        // m
    double free_radius_sigma = nan;  // m
    double radius_deviation = nan;   // m, free − known

    // Geometry of the visible cap: λ_min of mean(u·uᵀ); 1/3 for a full hemisphere, ≈ 0.06
    // for a cap of 30° half-angle, 0 for points on one line of sight.
    double coverage = nan;

    bool found() const { return status == SphereFitStatus::found; }
};

// `points` are the scan points near `predicted_centre` (through the grid's angular window or
// a spatial index); coordinates in metres, any frame.
SphereFit fit_sphere(std::span<const Eigen::Vector3d> points,
                     const Eigen::Vector3d& predicted_centre, const SphereFitParams& params);

}  // namespace tlsmon::registration
