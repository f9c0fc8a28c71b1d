#pragma once
// Deformation as the change of a primitive's parameters between the reference epoch and an
// epoch, both fitted in the reference's frame (primitive.hpp), with its covariance and tests
// (docs/primitives.md):
//   Δx = x_epoch − x_reference,   Σ_Δ = Σ_reference + Σ_epoch + J·Σ_T·Jᵀ
// where Σ_T is the epoch registration's covariance of (θx, θy, θz, tx, ty, tz, s) and J the
// change of the primitive's parameters when the epoch's points move as the registration's
// error moves them (δp = δθ × (p − t) + δt + δs·(p − t); algorithms/registration/
// registration_error.hpp). The two fits share no points' errors, so their covariances add.
#include <Eigen/Core>

#include "algorithms/primitives/primitive.hpp"

namespace tlsmon::primitives {

// J (u × 7): the parameters' change per unit of (δθ, δt, δs) of a rigid motion (and scale)
// about `centre`, to first order.
Eigen::MatrixXd motion_jacobian(const Primitive& primitive, const Eigen::Vector3d& centre);

// A test of a vector of changes v (k components) with covariance Σ at level α:
// T = vᵀ·Σ⁻¹·v against χ²(k, 1 − α). `lod` is the magnitude at which a change in v's
// direction would be significant, √(χ²(k, 1 − α) / (v̂ᵀ·Σ⁻¹·v̂)), so ‖v‖ > lod ⟺ T > limit;
// for k = 1 it is z(1 − α/2)·σ, the LoD95 at α = 0.05.
struct VectorTest {
    double magnitude = 0.0;
    double statistic = 0.0;
    double limit = 0.0;
    double lod = 0.0;
    bool significant = false;
};
VectorTest test_change(const Eigen::VectorXd& v, const Eigen::MatrixXd& covariance, double alpha);

struct Change {
    Eigen::VectorXd delta;
    Eigen::MatrixXd covariance;
};

// `registration_covariance` (7 × 7) zero when the epoch has no registration error to add.
Change parameter_change(const Primitive& reference, const Eigen::MatrixXd& reference_covariance,
                        const Primitive& epoch, const Eigen::MatrixXd& epoch_covariance,
                        const Eigen::Matrix<double, 7, 7>& registration_covariance,
                        const Eigen::Vector3d& registration_centre);

}  // namespace tlsmon::primitives
