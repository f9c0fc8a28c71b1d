#pragma once
// Cubic convolution (Keys 1981, "Cubic convolution interpolation for digital image
// processing", IEEE Trans. ASSP 29(6), eq. 15, a = −0.5): the interpolant of the image
// correlations (image_correlation.hpp, keypoints/patch_refinement.hpp), with its gradient
// taken from the same kernel, so that the gradient is the derivative of the values compared.
#include "algorithms/image.hpp"

namespace tlsmon {

struct CubicSample {
    double value = 0.0, d_row = 0.0, d_column = 0.0;
};

// The interpolant at (row, column) and its gradient; false where any of the 4 × 4 pixels it
// needs is outside the image or empty.
bool cubic_interpolate(const Image& image, double row, double column, CubicSample& out);

}  // namespace tlsmon
