#pragma once
// Keys' cubic convolution kernel (Keys 1981, "Cubic convolution interpolation for digital
// image processing", IEEE Trans. ASSP 29(6), eq. 15, a = −0.5) and its derivative: the
// interpolant of the image correlations (image_correlation.hpp, keypoints/patch_refinement.hpp).
#include <cmath>

namespace tlsmon {

inline double keys(double t) {
    constexpr double a = -0.5;
    const double s = std::abs(t);
    if (s <= 1.0) return ((a + 2.0) * s - (a + 3.0)) * s * s + 1.0;
    if (s < 2.0) return ((a * s - 5.0 * a) * s + 8.0 * a) * s - 4.0 * a;
    return 0.0;
}

inline double keys_derivative(double t) {
    constexpr double a = -0.5;
    const double s = std::abs(t), sign = t < 0.0 ? -1.0 : 1.0;
    if (s <= 1.0) return sign * (3.0 * (a + 2.0) * s - 2.0 * (a + 3.0)) * s;
    if (s < 2.0) return sign * ((3.0 * a * s - 10.0 * a) * s + 8.0 * a);
    return 0.0;
}

}  // namespace tlsmon
