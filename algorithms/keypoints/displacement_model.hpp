#pragma once
// Step 7 of the keypoint method (Hochmoselbrücke case study): a bivariate cubic
//   d(t, z) = Σ c_pq t^p z^q,  p + q ≤ 3  (10 terms)
// fitted with least absolute residuals over every segment's displacement d at time (or
// temperature) t and height z, all epochs so far. Definitions (docs/keypoints.md, pinned by
// tests/algorithms/test_keypoint_model.cpp):
// - Conditioning: the fit runs in u = (t − t_centre)/t_scale and w = (z − z_centre)/z_scale,
//   centre the middle and scale the half-width of the observed range (1 for a zero range),
//   so every monomial lies in [−1, 1]; `coefficients` are in u and w, `raw_coefficients()`
//   expands them into c_pq in t and z (ill-conditioned when t is far from 0, e.g. Unix
//   seconds: give t from the reference epoch, in days, or a temperature).
// - Least absolute residuals by iteratively reweighted least squares (Schlossmacher 1973,
//   "An iterative technique for absolute deviations curve fitting", JASA 68, 857–859):
//   start from ordinary least squares, then weights w_i = 1 / max(|r_i|, ε) with
//   ε = epsilon · max_i |d_i − median d|, until no coefficient moves by more than
//   tolerance · max_i |d_i − median d| or max_iterations. The iterate with the smallest
//   Σ|r_i| is returned, with the number of iterations and whether it converged.
// - Undefined (defined() false, reason given, coefficients NaN): fewer than 10
//   observations, or (t, z) points that cannot carry all 10 terms — all at one t or one z,
//   on one line, or fewer than 4 distinct values of either. Non-finite input throws.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

namespace tlsmon::keypoints {

struct ModelObservation {
    double t = 0;  // time (e.g. days since the reference epoch) or temperature
    double z = 0;  // height of the segment, m
    double d = 0;  // displacement, m
};

struct ModelTerm {
    int p, q;  // t^p z^q
};
// The terms in the order of the coefficient vectors: by total degree, then falling p.
inline constexpr std::array<ModelTerm, 10> kModelTerms{{
    {0, 0},
    {1, 0},
    {0, 1},
    {2, 0},
    {1, 1},
    {0, 2},
    {3, 0},
    {2, 1},
    {1, 2},
    {0, 3},
}};

struct ModelParameters {
    // IRLS for L1 converges linearly, slower the more residuals end at 0: about 140
    // solves for 500 noisy observations. 1e-6 of the spread of d (≈ 20 nm for a 20 mm
    // spread) is far below what a keypoint measures.
    std::size_t max_iterations = 1000;
    double tolerance = 1e-6;  // relative to the spread of d, see above
    double epsilon = 1e-8;    // relative to the spread of d: the smallest |r| weighted
};

using ModelCoefficients = Eigen::Matrix<double, 10, 1>;

struct DisplacementModel {
    double t_centre = 0, t_scale = 1, z_centre = 0, z_scale = 1;
    ModelCoefficients coefficients =
        ModelCoefficients::Constant(std::numeric_limits<double>::quiet_NaN());  // in u, w
    Eigen::VectorXd residuals;  // d − model, per observation in the input's order
    double sum_abs_residuals = std::numeric_limits<double>::quiet_NaN();
    double residual_scale = std::numeric_limits<double>::quiet_NaN();  // 1.4826 · MAD of r
    std::size_t observations = 0;
    std::size_t iterations = 0;  // reweighted solves after the least-squares start
    bool converged = false;
    std::string undefined_reason;  // empty when defined

    bool defined() const { return undefined_reason.empty(); }
    double operator()(double t, double z) const;
    // c_pq in t and z, in kModelTerms order.
    ModelCoefficients raw_coefficients() const;
};

DisplacementModel fit_displacement_model(std::span<const ModelObservation> observations,
                                         const ModelParameters& parameters = {});

}  // namespace tlsmon::keypoints
