#pragma once
// The centre of a planar 2×2 checkerboard target (the corner the four squares share) from
// the intensity of its scan points, to a fraction of the point spacing.
//
// 1. Plane: the points within 0.75 · size of the approximate centre, fitted by principal
//    components and refitted on the inliers, |distance| ≤ max(3 · 1.4826 · MAD, 0.5 mm),
//    until the inliers stop changing (mixed pixels at the board's rim and the background
//    fall out); then weighted by colour: the points within three times that window split
//    into the dark and the bright squares at the inliers' isodata intensity threshold
//    (Ridler & Calvard 1978), each colour's σ 1.4826 · median |distance| of its own points,
//    a point kept within 3.5 of its colour's σ and weighted 1/σ², refitted three times. The
//    offset's variance is s0²/Σw, s0² = Σ w·d² / (n − 3). Why: the signal model makes the
//    dark squares' ranges several times noisier than the bright ones' (as a scanner's range
//    noise grows as its return weakens).
//    One window for both (set by the bright ones) cut into the dark ones: the plane was then
//    a skipped mean, whose variance is E[ψ²] / E[ψ′]² with E[ψ′] = P(|d| ≤ c) − 2c·f(c)
//    (Huber & Ronchetti 2009, §3.2), and σ²/n along the normal came out 8–21 % too small
//    (RMS(error/σ) 1.08–1.21 on `pier`'s four boards); a wider last window kept the
//    precision and was honest on the seeds it was chosen on, not on others (1.00–1.13). By
//    colour, each clip lies in its own tail, and the dark squares weigh what they hold: the
//    offset's error is 28–36 % smaller and RMS(error/σ) 0.97–1.05
//    (tests/simulator/test_checkerboard_from_intensity.cpp; docs/registration.md, "A
//    checkerboard's centre along its normal").
// 2. The inliers are projected onto the plane: coordinates (a, b) along a horizontal axis
//    of the plane (to the right seen from the viewpoint) and the axis up the plane (for a
//    level board, along its edges).
// 3. Intensity model of a 2×2 checker seen through a Gaussian beam: the ideal pattern
//    sign(a′)·sign(b′) is separable, so its convolution with an isotropic Gaussian of
//    standard deviation σ is the product of two blurred steps,
//      I(a, b) = m + h · erf(a′ / (√2 σ)) · erf(b′ / (√2 σ)),
//      (a′, b′) = R(−θ) · ((a, b) − c),
//    with centre c, rotation θ, blur σ, mean level m and half-contrast h (h < 0 swaps the
//    colours, so θ within ±45° covers every orientation). Fitted by Levenberg–Marquardt to
//    the points within 0.4 · size of the centre (clear of the board's outer edges), the
//    window recentred once on the first fit.
// 4. Weights: the residuals' variance is modelled as σᵢ² = σ_I² + σ_p² · |∇Iᵢ|², the
//    intensity noise plus a position noise of the points along the pattern's gradient (the
//    beam's angular noise moves where the intensity was sampled against where the point is
//    placed: 0.5 mm at 36 m for 3″, which on an edge outweighs the intensity noise), fitted
//    to the squared residuals by least squares; the fit is repeated with weights 1/σᵢ²
//    (twice). Unweighted, the edge points, which carry the centre, would be trusted as
//    much as the flat squares and the σ would come out 2–3 times too small.
// 5. Covariance: σ̂₀² (JᵀWJ)⁻¹ (σ̂₀² = Σ wᵢ eᵢ² / (n − 6)) for the centre within the plane,
//    plus the plane's offset variance σ_d² / n along its normal. Honest when the errors are
//    independent and the model fits (the beam profile close to a Gaussian); a correlated
//    error (a smudge on the board) is not in it.
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace tlsmon {

struct CheckerboardSearch {
    Eigen::Vector3d approximate_centre = Eigen::Vector3d::Zero();  // within a few cm
    double size = 0.40;                                            // side of the board, m
    // The scanner's position: the plane's normal is turned towards it, which fixes the sense
    // of the in-plane axis a (to the right seen from there) and so of the rotation θ.
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
    int max_iterations = 100;
    // Refused as undersampled when the fitted blur σ is below this times the point spacing
    // (√(area / points) of the fitted window).
    double min_blur_to_spacing = 0.25;
};

struct CheckerboardCentre {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // m²
    // Of the fitted plane, unit, turned towards the viewpoint.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    double rotation = 0.0;            // θ, rad, of the pattern in the plane's (a, b) axes
    double blur_sigma = 0.0;          // σ of the fitted Gaussian blur, m
    double dark = 0.0, bright = 0.0;  // m − |h| and m + |h|
    double residual_rms = 0.0;        // intensity
    std::size_t plane_points = 0;     // inliers of the plane
    std::size_t fit_points = 0;       // used in the intensity fit
    int iterations = 0;
    double point_spacing = 0.0;  // m, √(area / points) of the intensity fit's window
};

// Throws tlsmon::Error when the points and intensities differ in number, the size is not
// positive, fewer than 50 points lie on the board, the fit does not converge, or the pattern
// is undersampled (its blur below min_blur_to_spacing times the point spacing).
CheckerboardCentre checkerboard_centre(const std::vector<Eigen::Vector3d>& xyz,
                                       const std::vector<float>& intensity,
                                       const CheckerboardSearch& search);

}  // namespace tlsmon
