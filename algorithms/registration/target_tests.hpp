#pragma once
// Tests of the registration adjustment, as in geodetic deformation analysis: an iterated
// per-target outlier test (data snooping, Baarda 1968) that excludes the worst target and
// re-adjusts while enough targets with usable geometry remain, and the global test of the
// variance factor on what is left. Too few targets, or targets on a line, give a refusal
// with its reason rather than a transformation.
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration {

enum class OutlierStatistic {
    // T_i = v_iᵀ·Q_vv,ii⁻¹·v_i ~ χ²(3): the target as one 3-D point; equals the drop of Ω when
    // the target is left out (Förstner 1983; the point localisation of the congruence test,
    // Niemeier 2008 §13.4 / Pelzer 1971).
    target_quadratic_form,
    // max_j |w_j| with Baarda's w_j = (P·v)_j / √(P·Q_vv·P)_jj ~ N(0, 1), per coordinate.
    largest_normalised_residual,
};

struct TargetTestParams {
    double global_alpha = 0.05;  // χ² test of the variance factor (one-sided: s0² too large)
    // A failed global test with no target to blame is not a refusal while Ω stays within
    // χ²(r, 1 − global_reject_alpha), the variance factor's hard limit: the covariance is
    // scaled by s0² and the registration is `accepted_scaled`. Beyond it, or with
    // global_reject_alpha = global_alpha, `global_test_failed`. (docs/registration.md,
    // "Global test policy".)
    double global_reject_alpha = 0.001;
    double target_alpha = 0.001;  // each outlier test (Baarda's α0 = 0.1 %)
    double power = 0.8;           // 1 − β for the minimal detectable bias (Baarda's β0 = 20 %)
    OutlierStatistic statistic = OutlierStatistic::target_quadratic_form;
    std::size_t min_targets = 3;  // used targets that must remain
    double min_spread = 0.5;      // m, RMS distance of the used centres from their best-fit line
    RigidTransformParams adjustment;
};

// One target offered to the registration.
struct TargetPair {
    CentreObservation centres;
    bool usable = true;  // false: not found in this epoch, or excluded until re-surveyed
};

enum class TargetUse {
    used,
    not_usable,        // not offered (not found, or excluded before this epoch)
    excluded_outlier,  // failed the outlier test in round `excluded_in_round`
    suspect,           // failed the outlier test but could not be excluded (too few left,
                       // or another target explains the misfit as well)
};

const char* describe(TargetUse use);

struct TargetVerdict {
    TargetUse use = TargetUse::not_usable;
    int excluded_in_round = 0;  // 1 for the first exclusion
    double statistic = 0.0;     // T_i, or max |w_j|, at its last test (0 if never tested)
    double critical = 0.0;      // its critical value
    int dof = 0;                // of T_i: rank of Q_vv,ii
    // Internal reliability (Baarda 1968): the size of a bias of this target's centre, in the
    // least favourable direction (given, reference frame), that its outlier test finds with
    // probability `power`. A smaller knock may go unnoticed; infinite when that direction is
    // absorbed by the transformation altogether.
    double minimal_detectable_bias = std::numeric_limits<double>::quiet_NaN();  // m
    Eigen::Vector3d weakest_direction = Eigen::Vector3d::Zero();
    // Residual under the final transformation, s·R·x + t − X: for an excluded target its
    // apparent movement (NaN without a transformation).
    Eigen::Vector3d residual = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

enum class RegistrationStatus {
    accepted,                  // all tests passed
    accepted_scaled,           // no outlier, the global test failed within its hard limit:
                               // the covariance is scaled by s0² (a posteriori or larger_of)
    global_test_failed,        // no target to blame, but the residuals exceed the covariances
    too_few_targets,           // refused: fewer than min_targets usable
    degenerate_geometry,       // refused: the used targets are (nearly) on a line
    outlier_not_excludable,    // refused: a target failed its test and excluding it leaves too few
    outlier_not_identifiable,  // refused: a misfit that another target explains as well
    planes_refused,        // refused: the registration on planes found too few, or no congruent set
    stable_areas_refused,  // refused: too small a stable share, or ill-conditioned
};

const char* describe(RegistrationStatus status);

struct GlobalTest {
    double omega_sq = 0.0;  // Ω = vᵀPv
    int redundancy = 0;
    double variance_factor = 0.0;  // s0² = Ω / r
    double critical = 0.0;         // χ²(r, 1 − α)
    bool passed = false;
    double hard_limit = 0.0;  // χ²(r, 1 − global_reject_alpha): Ω beyond it is refused
};

struct TestedRegistration {
    RegistrationStatus status = RegistrationStatus::too_few_targets;
    std::string reason;                       // for anything but `accepted`
    std::optional<RigidTransform> transform;  // the last adjustment; trust it only if accepted
    std::vector<TargetVerdict> targets;       // in the order given
    GlobalTest global;
    int rounds = 0;       // adjustments made
    double spread = 0.0;  // m, geometry of the used targets (see min_spread)

    // Accepted, or accepted with its covariance scaled by s0²: usable either way.
    bool accepted() const {
        return status == RegistrationStatus::accepted ||
               status == RegistrationStatus::accepted_scaled;
    }
};

// RMS distance (m) of the points from their best-fit line: √(λ₂ + λ₃) of their scatter.
double spread_about_line(std::span<const Eigen::Vector3d> points);

TestedRegistration register_with_tests(std::span<const TargetPair> targets,
                                       const TargetTestParams& params);

}  // namespace tlsmon::registration
