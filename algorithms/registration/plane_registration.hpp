#pragma once
// Registration on planes: the rigid transformation X_ref = R·x + t from planes seen in both
// frames, each with the covariance of its normal and centroid (plane_fit.hpp), by a
// weighted least-squares adjustment linearised in small rotations; and the congruence test
// (geodetic deformation analysis: Pelzer 1971; Niemeier 2008, ch. 13) that finds the planes
// that moved and keeps the datum on the planes that stayed.
//
// Per correspondence i (reference plane n_r, c_r; epoch plane n_e, c_e) three misclosures,
// zero for an unmoved plane under the true transformation:
//
//   w_u = u·(R·n_e),  w_v = v·(R·n_e)      the tilt of the mapped normal towards the
//                                          reference plane's axes u (longest), v = n_r × u, rad
//   w_d = n_r·(R·c_e + t − c_r)            the mapped epoch centroid's distance from the
//                                          reference plane along n_r, m
//
// Their covariance (σ0 = 1), by propagation of both planes' (a = R·c_e + t − c_r, U = [u v]):
//
//   Σ_ww = | Uᵀ(Σ_nr + R·Σ_ne·Rᵀ)U     −Uᵀ·Σ_nr·a          |
//          | −aᵀ·Σ_nr·U                aᵀ·Σ_nr·a + σ²_cr + σ²_ce |
//
// and their derivatives by the rotation increment θ (R̂ = exp([θ]×)·R) and t:
// ∂w_{u,v}/∂θ = −U ᵀ[R·n_e]×, ∂w_d/∂θ = −n_rᵀ[R·c_e]×, ∂w_d/∂t = n_rᵀ. Three misclosures
// per plane, six parameters: r = 3n − 6; at least three planes whose normals span space.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "algorithms/registration/plane_fit.hpp"
#include "algorithms/registration/rigid_transform.hpp"

namespace tlsmon::registration {

// One plane seen in both frames (the normals' signs need not agree: the epoch's is turned
// towards the reference's under the transformation).
struct PlaneCorrespondence {
    FittedPlane reference;  // in the reference frame
    FittedPlane epoch;      // in the epoch's frame
};

// One correspondence under the adjusted transformation.
struct PlaneMisclosure {
    Eigen::Vector3d w = Eigen::Vector3d::Zero();           // (w_u, w_v) rad, w_d m, as above
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // Σ_ww (σ0 = 1)
    // In the adjustment: Q_vv = Σ_ww − J·Q_xx·Jᵀ; left out of it: Σ_ww + J·Q_xx·Jᵀ (the
    // prediction's uncertainty added). Either way the cofactor of w itself.
    Eigen::Matrix3d cofactor = Eigen::Matrix3d::Zero();
    // T = wᵀ·cofactor⁻¹·w ~ χ²(3) if the plane did not move (in the adjustment: the drop of
    // Ω when it is left out; Förstner 1983).
    double test_statistic = 0.0;
    bool in_adjustment = true;

    // The plane's apparent motion: tilt of its normal (rad, the larger principal component
    // is not separated: √(w_u² + w_v²)) and shift along the reference normal (m).
    double tilt() const { return w.head<2>().norm(); }
    double shift() const { return w(2); }
};

// One correspondence's misclosure w and Σ_ww under (R, t) (the equations above); its
// cofactor is Σ_ww and its test statistic wᵀ·Σ_ww⁻¹·w (the two planes' difference alone, as
// when two touching planes of one scan are compared: R = I, t = 0).
PlaneMisclosure plane_misclosure(const PlaneCorrespondence& planes, const Eigen::Matrix3d& R,
                                 const Eigen::Vector3d& t);

struct PlaneAdjustment {
    RigidTransform transform;  // `residuals` empty; Ω, r, s0², covariance as for targets
    std::vector<PlaneMisclosure> planes;  // in the order of the correspondences given
};

// The adjustment on the correspondences with `use[i]` (all when empty), starting from
// `start` (the previous epoch's or the targets' transformation; identity for a fixed
// station); every correspondence's misclosure under the result. Throws tlsmon::Error for
// fewer than three planes in use, a singular normal matrix (normals that do not span
// space), or no convergence.
PlaneAdjustment adjust_planes(std::span<const PlaneCorrespondence> planes,
                              const std::vector<bool>& use, const RigidTransform& start,
                              const RigidTransformParams& params = {});

struct CongruenceParams {
    double alpha = 0.05;         // the global test: Ω > χ²(r, 1 − α) → something moved
    std::size_t min_planes = 4;  // planes that must stay in the datum
    RigidTransformParams adjustment{.scaling = CovarianceScaling::a_priori};
};

struct CongruenceResult {
    PlaneAdjustment adjustment;        // on the planes that stayed
    std::vector<std::size_t> moved;    // in the order they were found
    std::vector<double> global_omega;  // Ω of each round, the first with every plane
    std::vector<double> global_limit;  // χ²(r, 1 − α) of each round
    bool congruent = false;            // the last round's global test passed
    std::string note;                  // why the localisation stopped, if not congruent
};

// The global test of "no plane moved" on every correspondence with `candidate[i]` (all when
// empty); while it fails, the plane with the largest T leaves the datum and the adjustment is
// repeated (the localisation of the congruence test), down to `min_planes`. A plane that is
// no candidate (one on the monitored structure) never enters the datum: its misclosure is
// predicted like a moved plane's.
CongruenceResult congruence_test(std::span<const PlaneCorrespondence> planes,
                                 const RigidTransform& start, const CongruenceParams& params = {},
                                 const std::vector<bool>& candidate = {});

}  // namespace tlsmon::registration
