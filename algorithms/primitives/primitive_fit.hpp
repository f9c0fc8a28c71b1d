#pragma once
// The fine fit of a primitive to a scan's points: a Gauss–Markov adjustment of the
// orthogonal distances (the condition equations of a Gauss–Helmert model with one condition
// per point reduce to it when each point's covariance is projected on the surface normal),
// weighted by the scanner's stochastic model, with stray returns and the silhouette left
// out (docs/primitives.md).
//
// Each point p seen along the unit beam s from the scanner at range ρ has, along the
// surface normal n (incidence ι, cos ι = |n·s|),
//   σ_n² = σ_r(ρ)²·cos²ι + (ρ·σ_θ)²·sin²ι
// (core/scanner_noise.hpp: σ_r = a + b·ρ, σ_θ the beam's angular σ). Iterations solve
// N·δ = Aᵀ·P·(−d) with N = Aᵀ·P·A (A the distances' gradients, P = diag(1/σ_n²)) until the
// step is below 1e-9 of the parameters' scale. Σ_x = σ0²·N⁻¹ with σ0² = max(1, s0²), s0² =
// Ω/(m − u): never more optimistic than the stochastic model nor than the residuals (as the
// registration's adjustment, algorithms/registration/rigid_transform.hpp).
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <string>

#include "algorithms/primitives/primitive.hpp"
#include "core/scanner_noise.hpp"

namespace tlsmon::primitives {

struct FitParameters {
    double band = 0.05;               // m, points farther than this from the start are not its
    double max_incidence_deg = 75.0;  // points seen more obliquely (the silhouette) left out
    double clip_k = 3.5;              // |d|/σ_n beyond k·max(1, robust s0): a stray return
    std::size_t min_points = 500;     // points needed for a fit
    int max_iterations = 30;
    unsigned threads = 0;  // 0: every core; the result does not depend on it
};

enum class FitStatus { fitted, too_few_points, not_converged, singular };
const char* to_string(FitStatus status);

struct Fit {
    FitStatus status = FitStatus::too_few_points;
    Primitive primitive;
    Eigen::MatrixXd covariance;  // of primitive.x, σ0²·N⁻¹
    double s0 = 0.0;             // a posteriori σ of unit weight, √(Ω/(m − u))
    double rms = 0.0;            // m, RMS of the used points' distances
    std::size_t candidates = 0;  // points within the band, seen within the incidence limit
    std::size_t used = 0;        // of those, not clipped
    int iterations = 0;
};

// The points (and `scanner`, the place they were seen from) in one frame. `start` gives the
// kind, the frame and the first parameters; the result keeps that frame.
Fit fit_primitive(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& scanner,
                  const ScannerNoise& noise, const Primitive& start, const FitParameters& params);

}  // namespace tlsmon::primitives
