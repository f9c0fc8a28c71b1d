#pragma once
// Where a template image lies in a search image, to a fraction of a pixel: normalised
// cross-correlation (NCC) over integer offsets for the peak, a parabola through the peak
// and its neighbours for a first sub-pixel shift, then least-squares image matching
// (Lucas & Kanade 1981; Gruen 1985, with a radiometric gain and offset):
//   S(p + o + s) ≈ g · T(p) + b   over the template's valid pixels p,
// solved by Gauss–Newton for the shift s and g, b, with S interpolated by its cubic
// B-spline (cubic_bspline.hpp) and the Jacobian from the template's gradient (the search
// image's noise kept out of it: see the .cpp). The parabola alone is biased towards whole
// pixels ("pixel locking"); the least-squares step only by the interpolant's phase error
// (≈ 0.0003 pixel at 0.12 cycles per pixel; Keys' cubic convolution, used before: 0.009).
//
// Convention: pixel (r, c) of the template sits on pixel (r + o_r, c + o_c) of the search
// image at zero shift; shift = (Δcolumn, Δrow) with T(r, c) ≈ S(r + o_r + Δrow,
// c + o_c + Δcolumn). For orthoimages of two epochs (template from the earlier) the shift
// times the pixel size is the surface's movement along the image's (u, v) axes.
#include <Eigen/Core>
#include <cstddef>

#include "algorithms/image.hpp"

namespace tlsmon {

struct CorrelationParameters {
    int search_radius = 5;  // integer offsets −R..R in rows and columns, pixels
    // An offset counts only where this share of the template's valid pixels meets valid
    // search pixels.
    double min_overlap = 0.9;
    int max_iterations = 30;    // least-squares matching
    double convergence = 1e-5;  // pixels: stop when the update is smaller
};

struct CorrelationResult {
    // False when no offset had the overlap, the NCC peak lies on the search border (the
    // shift may be outside the search range), or the least-squares matching diverged.
    bool found = false;
    Eigen::Vector2d shift = Eigen::Vector2d::Zero();  // (Δcolumn, Δrow), pixels
    // Of the shift, pixels², from the least-squares residuals: σ̂² (JᵀJ)⁻¹ with
    // σ̂² = Σe² / (n − 4); treats the pixels' errors as independent, so for images smoothed
    // before matching (an orthoimage's kernel) it is a lower bound.
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
    double peak_ncc = 0.0;   // NCC at the best integer offset
    double ncc = 0.0;        // NCC at the final shift (the quality: 1 = identical up to g, b)
    std::size_t pixels = 0;  // template pixels used in the least-squares matching
    int iterations = 0;
};

// Throws tlsmon::Error for mismatched image and mask shapes, a negative search radius, or
// an empty template.
CorrelationResult correlate_template(const Image& templ, const Image& search,
                                     const Eigen::Vector2i& origin_row_column,
                                     const CorrelationParameters& parameters = {});

// NCC of two equally long samples (the Pearson correlation); 0 when either is constant.
double normalised_cross_correlation(const Eigen::ArrayXd& a, const Eigen::ArrayXd& b);

}  // namespace tlsmon
