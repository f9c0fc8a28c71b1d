#pragma once
// Cubic B-spline interpolation of an image (Unser 1999, "Splines: a perfect fit for signal
// and image processing", IEEE Signal Process. Mag. 16(6), 22–38): the interpolant
//   f(y, x) = Σ_k Σ_l c(k, l) β³(y − k) β³(x − l)
// passes through every sample; its coefficients c come from the samples by the recursive
// filter of Unser, Aldroubi & Eden (1993, IEEE Trans. Signal Process. 41(2), 821–833, pole
// z = √3 − 2, mirror-symmetric ends), along the rows, then the columns.
//
// Why not cubic convolution (Keys 1981, IEEE Trans. ASSP 29(6), a = −0.5), which the
// correlations used before: a correlation's shift is biased by its interpolant's phase
// error at the fraction t of a pixel it samples at (Schreier, Braasch & Sutton 2000,
// "Systematic errors in digital image correlation caused by intensity interpolation", Opt.
// Eng. 39(11), 2915–2921). At t = ¼ and 0.1 (0.2) cycles per pixel Keys' kernel pulls a
// shift by 0.0063 (0.027) pixel, the cubic B-spline by 0.00013 (0.0025) pixel: odd about
// t = ½, and the same for every patch of an image that moved as a whole, so no standard
// error over the patches sees it (docs/keypoints.md, "The lattice's phase").
//
// An image with empty pixels: each maximal run of valid pixels along a row, then along a
// column, is filtered on its own, with its own mirror ends; an empty pixel's coefficient is
// 0 and invalid.
#include "algorithms/image.hpp"

namespace tlsmon {

struct CubicSample {
    double value = 0.0, d_row = 0.0, d_column = 0.0;
};

// The coefficients c of an image's cubic B-spline, on the image's pixels and validity.
struct BSplineImage {
    Image coefficients;
};

BSplineImage bspline_image(const Image& samples);

// The interpolant at (row, column) and its gradient (the same spline's derivative, so that
// the gradient is the derivative of the values compared); false where any of the 4 × 4
// coefficients it needs is outside the image or empty.
bool bspline_interpolate(const BSplineImage& image, double row, double column, CubicSample& out);

}  // namespace tlsmon
