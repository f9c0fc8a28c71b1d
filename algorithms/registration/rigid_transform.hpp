#pragma once
// The rigid transformation (rotation + translation, scale optional) that maps an epoch's
// frame into the reference frame, from target centres seen in both, each with its 3×3
// covariance: a closed-form start (Umeyama 1991) and a weighted least-squares adjustment
// linearised in small rotations, with the parameters' covariance, per-target residuals,
// their cofactors and the a posteriori variance factor.
//
//   X_ref = s·R·x_epoch + t,   R = R_z(κ)·R_y(φ)·R_x(ω)
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>
#include <vector>

namespace tlsmon::registration {

// One target's centre in both frames, covariances in m².
struct CentreObservation {
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // reference frame (epoch 0 or survey)
    Eigen::Matrix3d reference_covariance = Eigen::Matrix3d::Zero();
    Eigen::Vector3d epoch = Eigen::Vector3d::Zero();  // this epoch's frame
    Eigen::Matrix3d epoch_covariance = Eigen::Matrix3d::Zero();
};

// Which variance factor scales the parameters' covariance σ0²·Q_xx.
enum class CovarianceScaling {
    a_priori,      // σ0² = 1: the centres' covariances are taken as they are
    a_posteriori,  // σ0² = s0² = Ω/r
    // max(1, s0²), the default: never more optimistic than the centres, nor the residuals.
    // It pads the 68 % interval (the epochs with s0² > 1 are scaled up); `a_priori` covers
    // at the nominal rates on the three scenes since the boards' σ along their normal is
    // honest (docs/calibration.md, "The registration's variance factor", says why the
    // default stays).
    larger_of,
};

// σ0² for `scaling` given the adjustment's s0² and its redundancy r. Scaling by s0² is honest
// when the observations' stochastic model is right up to one common factor, which s0²
// estimates — but with r degrees of freedom, so (x̂ − x)/σ̂ follows Student's t(r), and
// ±1.96 σ̂ covers only 92 % at r = 9 (five targets). Wherever s0² sets the factor it is
// therefore multiplied by (t(0.975, r) / 1.96)²: the σ stored is the normal-equivalent one,
// whose 1.96 σ is the 95 % interval every LoD95 downstream takes it for
// (tests/algorithms/test_rigid_transform.cpp, ScalingByS0Squared…; docs/calibration.md).
// r = 0: nothing to estimate s0² from, the a priori factor 1.
double covariance_factor(CovarianceScaling scaling, double variance_factor, int redundancy);
// (t(0.975, r) / 1.96)², 1 for r ≤ 0.
double t_expansion(int redundancy);

struct RigidTransformParams {
    bool estimate_scale = false;
    CovarianceScaling scaling = CovarianceScaling::larger_of;
    int max_iterations = 20;
};

// Per-target result of the adjustment (reference frame, metres).
struct CentreResidual {
    Eigen::Vector3d residual;       // v = s·R·x + t − X: where the target appears to have moved
    Eigen::Matrix3d cofactor;       // Q_vv,ii = Q_ll,ii − A_i·Q_xx·A_iᵀ (σ0 = 1)
    Eigen::Vector3d sigma;          // √diag(Q_vv,ii)
    Eigen::Vector3d normalised;     // v / σ per component (Baarda's w for uncorrelated centres)
    double redundancy_share = 0.0;  // tr(Q_vv,ii·P_i): this target's part of the redundancy
};

// Parameter vector order everywhere: (ω, φ, κ, tx, ty, tz, s) for the Euler covariance and
// (θx, θy, θz, tx, ty, tz, s) for the small-rotation covariance, R̂ = exp([θ]×)·R.
// Rows and columns of s are zero when the scale is not estimated.
using ParameterCovariance = Eigen::Matrix<double, 7, 7>;

struct RigidTransform {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    double scale = 1.0;
    Eigen::Quaterniond quaternion = Eigen::Quaterniond::Identity();
    double omega = 0.0, phi = 0.0, kappa = 0.0;  // rad

    bool scale_estimated = false;
    ParameterCovariance covariance = ParameterCovariance::Zero();  // Euler angles
    ParameterCovariance small_rotation_covariance = ParameterCovariance::Zero();
    std::vector<CentreResidual> residuals;  // in the order of the observations given

    double omega_sq = 0.0;           // Ω = Σ vᵢᵀ·Pᵢ·vᵢ
    int redundancy = 0;              // r = 3n − u
    double variance_factor = 0.0;    // s0² = Ω / r
    double covariance_factor = 1.0;  // σ0² used for `covariance` (see CovarianceScaling)
    int iterations = 0;

    Eigen::Vector3d apply(const Eigen::Vector3d& p) const {
        return scale * (rotation * p) + translation;
    }
    // 4×4 homogeneous matrix (column-vector form) mapping epoch points into the reference frame.
    Eigen::Matrix4d matrix() const;
    Eigen::Vector<double, 7> sigmas() const { return covariance.diagonal().cwiseSqrt(); }
};

// After an adjustment has set `rotation` and `small_rotation_covariance`: the Euler angles,
// the quaternion (w ≥ 0) and the Euler angles' covariance `covariance`.
void finish_parameters(RigidTransform& T);

// R = R_z(κ)·R_y(φ)·R_x(ω) and back (φ in [−90°, 90°]).
Eigen::Matrix3d rotation_from_euler(double omega, double phi, double kappa);
Eigen::Vector3d euler_from_rotation(const Eigen::Matrix3d& R);

// Closed form: the least-squares similarity (or rigid, scale = 1) transformation between two
// point sets with scalar weights (Umeyama 1991, Theorem / eqs. 40–42; Horn 1987 for the
// rigid case). Needs ≥ 3 points not on a line.
RigidTransform closed_form_transform(std::span<const CentreObservation> centres,
                                     bool estimate_scale);

// The weighted least-squares adjustment. Throws tlsmon::Error for fewer than 3 centres or a
// singular normal matrix (collinear targets).
RigidTransform estimate_rigid_transform(std::span<const CentreObservation> centres,
                                        const RigidTransformParams& params);

// The residual of a centre under a given transformation: s·R·x + t − X (its apparent
// movement, e.g. for a target left out of the adjustment).
inline Eigen::Vector3d centre_residual(const RigidTransform& T, const CentreObservation& c) {
    return T.apply(c.epoch) - c.reference;
}

}  // namespace tlsmon::registration
