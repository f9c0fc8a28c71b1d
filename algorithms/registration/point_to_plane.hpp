#pragma once
// The point-to-plane adjustment that ends an ICP on stable regions, with an honest covariance,
// and the combination of two independent estimates of the same transformation.
//
// Each pair is an epoch point x (epoch frame), the reference point q it was matched to and
// the reference surface's unit normal n there; the observation is the distance along n,
//   v = nᵀ·(R·x + t − q)                                   (Chen & Medioni 1992)
// linearised in a small rotation θ (R̂ = exp([θ]×)·R, as in rigid_transform.hpp) and a
// translation increment: design row aᵀ = [ (R·x × n)ᵀ, nᵀ ].
//
// Each pair may carry a weight p = σ₀²/σ² (its surface's noise); then N = Σ p·a·aᵀ,
// s0² = Σ p·v²/(n − 6) is the unit weight's variance and g_k = Σ p·a·v below.
//
// Covariance of (θ, t): the classical s0²·N⁻¹ (N = Σ a·aᵀ, s0² = vᵀv/(n − 6)) takes every
// pair as independent. A scan's residuals are not: the footprint, the grid's phase, mixed
// returns at edges and the voxel centroids err alike over a patch of surface. The pairs are
// therefore grouped into cells of `cluster_size` (by the reference point) and the
// cluster-robust sandwich
//   Σ_c = c/(c − 1)·(n − 1)/(n − 6)·N⁻¹·(Σ_k g_k·g_kᵀ)·N⁻¹,   g_k = Σ_{i ∈ k} a_i·v_i
// (Liang & Zeger 1986; the small-sample factor of Cameron & Miller 2015, §VI.A) lets each
// cell's residuals be correlated in any way. But with few cells in a direction the sandwich
// itself is noisy and small; so a random-effects model of the cells as well: an error u_c
// common to the pairs of cell c, of variance τ² estimated by moments from the cells' sum of
// squares (the ANOVA estimator, each cell by its weight, its expectation taken through the
// fit), gives N⁻¹·(s0²·N + τ²·Σ_c b_c·b_cᵀ)·N⁻¹ (b_c = Σ_{i ∈ c} p_i·a_i). The reported
// covariance is the largest of the three in the matrix sense (every direction's variance at
// least each one's): never more optimistic than independent noise.
#include <Eigen/Core>
#include <cstddef>
#include <span>

#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration {

struct PointPlanePair {
    Eigen::Vector3d epoch = Eigen::Vector3d::Zero();      // epoch frame
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // reference frame
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();    // unit, at `reference`
    // p = σ₀²/σ² of the distance (1: every pair alike); s0² is then the unit weight's variance.
    double weight = 1.0;
};

struct PointToPlaneParams {
    double cluster_size = 1.0;  // m, side of the cells whose residuals may be correlated
    // A corner of the cells' grid. A cell face in a surface splits the surface's reference
    // points by their noise along its normal, and the two cells' mean residuals then carry
    // that noise's sign: a common error of the cells that the scan does not have, which
    // cancels in the estimate (both sides hold the same directions) and pads the σ. The ICP
    // puts the cells on its voxel grid, off the whole centimetres where built faces lie.
    Eigen::Vector3d cell_origin = Eigen::Vector3d::Zero();
    // The cells' random-effects term in the reported covariance (a caller with a model of its
    // own at another level, as the stable areas' supervoxels, leaves it out).
    bool cell_effect = true;
    int iterations = 3;  // Gauss–Newton steps on the fixed pairs
    // After the first solution, pairs farther than outlier_k·σ̂ from their plane are left out
    // (σ̂ = 1.4826·MAD of the distances √p·v, at least `min_sigma`) and the fit repeated: a pair
    // across an edge, a leaf, a person. 0: all pairs kept.
    double outlier_k = 4.0;
    double min_sigma = 0.0002;  // m
};

using Covariance6 = Eigen::Matrix<double, 6, 6>;

struct PointToPlaneFit {
    RigidTransform transform;  // covariance of (θ, t) and the Euler angles filled in
    std::size_t pairs = 0;     // used
    std::size_t outliers = 0;  // left out beyond outlier_k·σ̂
    std::size_t clusters = 0;
    double rms = 0.0;              // m, RMS of the distances v after the fit
    double variance_factor = 0.0;  // s0² = Σ p·v²/(n − 6), m² (per unit weight)
    Covariance6 independent;       // s0²·N⁻¹
    Covariance6 clustered;         // the sandwich Σ_c
    // Per parameter, the degrees of freedom of the sandwich's variance (Bell & McCaffrey 2002,
    // as Imbens & Kolesár 2016 give them): few cells holding a direction make it scatter.
    Eigen::Matrix<double, 6, 1> clustered_dof = Eigen::Matrix<double, 6, 1>::Constant(1e9);
    Covariance6 cell_effect;  // s0²·N⁻¹ + τ²·N⁻¹·Σ b_c·b_cᵀ·N⁻¹ (point_to_plane.cpp)
    double cell_sigma = 0.0;  // τ, m: the error common to each cell, by moments
    double inflation = 1.0;   // largest σ ratio of the reported covariance to s0²·N⁻¹
    double condition = 0.0;   // of N scaled to unit diagonal: large = a direction unheld
};

// Gauss–Newton on Σ v² from `start` (4×4, epoch -> reference) with the pairs fixed. Throws
// tlsmon::Error with fewer than 7 pairs or a singular normal matrix (the pairs' planes do
// not hold every direction).
PointToPlaneFit fit_point_to_plane(std::span<const PointPlanePair> pairs,
                                   const Eigen::Matrix4d& start, const PointToPlaneParams& params);

// The larger of two covariances in the matrix sense: every direction's variance at least
// `floor`'s and at least `other`'s (`other` itself when `floor` is singular).
Covariance6 larger_of(const Covariance6& floor, const Covariance6& other);
Eigen::MatrixXd larger_of(const Eigen::MatrixXd& floor, const Eigen::MatrixXd& other);

// A RigidTransform from a rotation, a translation and the covariance of (θ, t): the Euler
// angles, the quaternion and the Euler covariance (Förstner & Wrobel 2016, §8.1.3) derived
// as estimate_rigid_transform derives them.
RigidTransform rigid_transform_from(const Eigen::Matrix3d& rotation,
                                    const Eigen::Vector3d& translation,
                                    const Covariance6& small_rotation_covariance);

// Two independent estimates a, b of the same rigid transformation combined by their weights:
// with b written as a correction δ of a (R_b = exp([δθ]×)·R_a, t_b = t_a + δt), the combined
// correction is (P_a + P_b)⁻¹·P_b·δ and its covariance (P_a + P_b)⁻¹ (P = Σ⁻¹ of (θ, t);
// Niemeier 2008 §3.3, the weighted mean). The scale is not combined (both rigid).
RigidTransform combine_transforms(const RigidTransform& a, const RigidTransform& b);

// Whether two independent estimates agree: dᵀ·(Σ_a + Σ_b)⁻¹·d of b's correction d of a (as
// above), ~ χ²(6) when both estimate the same transformation.
double transform_difference_statistic(const RigidTransform& a, const RigidTransform& b);

}  // namespace tlsmon::registration
