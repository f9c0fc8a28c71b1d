#pragma once
// The variance the areas' own covariances do not see (docs/vectors.md, "Uncertainty"): the
// areas of a zone measured in one epoch, about a smooth field over the zone, scatter more than
// their σ says — an area's texture sampled by the scanner's lattice errs as a whole (a joint
// narrower than the spacing moves the match by a share of the sub-spacing shift, the same in
// every block of the area), which no estimate inside the area can see, and which differs from
// area to area. That part is estimated across the areas as a variance component τ², by the
// method of moments for meta-regression (DerSimonian & Laird 1986; Raudenbush 2009, eq. 16.14):
//     y_k = x_kᵀβ + e_k,   Var(e_k) = s_k² + τ²,
//     Q = Σ w_k r_k² (w_k = 1/s_k², r the weighted least-squares residuals),
//     τ² = max(0, (Q − (n − p)) / (Σ w_k − tr((XᵀWX)⁻¹ XᵀW²X))).
// When the areas' σ are honest, Q ≈ n − p and τ² ≈ 0.
#include <Eigen/Core>

namespace tlsmon::vectors {

struct BetweenAreaVariance {
    double tau2 = 0;       // m², the variance component (0 when it cannot be estimated)
    double q = 0;          // the weighted residual sum of squares
    Eigen::Index dof = 0;  // n − p; 0: too few areas for the field, τ² not estimated
};

// τ² of `values` with `variances` about the field spanned by the columns of `field` (one row
// per area). Needs n > p + 1 and positive variances; otherwise dof = 0 and τ² = 0.
BetweenAreaVariance between_area_variance(const Eigen::MatrixXd& field,
                                          const Eigen::VectorXd& values,
                                          const Eigen::VectorXd& variances);

// The smooth field over a zone at positions (h, v) in its wall (m): a quadratic surface —
// the face of a pier in bending moves along itself as a quadratic in height — when there are
// at least `kQuadraticAreas` areas, else a plane.
Eigen::MatrixXd zone_field(const Eigen::MatrixX2d& positions);
inline constexpr Eigen::Index kQuadraticAreas = 20;

}  // namespace tlsmon::vectors
