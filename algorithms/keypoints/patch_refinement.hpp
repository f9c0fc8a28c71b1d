#pragma once
// Sub-pixel refinement of a match by least-squares image matching (Grün 1985, "Adaptive
// least squares correlation: a powerful image matching technique", S. Afr. J. Photogramm.
// 14(3), 175–187; here with a shift and a linear radiometric model only): a square patch of
// the reference's intensity around a pixel is sought in the epoch's intensity image,
//   P(i, j) ≈ g · E(r + i + Δr, c + j + Δc) + o,
// solved for (Δr, Δc, g, o) by Gauss–Newton, E bilinearly interpolated, its gradient by
// central differences interpolated the same way.
//
// Why: a detector's keypoint is placed to a tenth of a pixel at best, and its error is not
// random between epochs: it is drawn towards the pixel lattice ("pixel locking"). When the
// scanner's lattice moves over the surface between epochs (its orientation drifts by
// arcseconds, corrected only afterwards by the registration), the keypoints stay with the
// lattice and report the drift as a movement of the surface — millimetres at 50 m on the
// simulated pier. The patch's position is found from all its pixels, and the reference's
// end is a pixel centre (an exact return, nothing interpolated).
#include <cstddef>
#include <optional>
#include <vector>

#include "algorithms/keypoints/spherical_image.hpp"

namespace tlsmon::keypoints {

// The reference's intensity at the (2·radius + 1)² pixels around (row, column), row-major.
struct IntensityPatch {
    int row = 0, column = 0;  // the centre pixel
    int radius = 0;
    std::vector<float> values;
};

// Nothing when a pixel of the patch lies outside the image or has no return.
std::optional<IntensityPatch> intensity_patch(const SphericalImages& images, int row, int column,
                                              int radius);

struct PatchMatchParameters {
    int max_iterations = 12;
    double tolerance = 1e-3;       // px: the shift's update below this ends the iteration
    double max_move = 2.0;         // px from the start: farther, the patch was not found
    double min_correlation = 0.6;  // normalised cross-correlation at the solution
};

struct PatchMatch {
    double row = 0, column = 0;  // where the patch centre lies in the epoch's image
    double correlation = 0;
    int iterations = 0;
};

// Starting from (row, column) in the epoch's image. Nothing when the patch runs into an
// empty pixel or the image's edge, does not converge, moves too far, or correlates poorly.
std::optional<PatchMatch> match_patch(const IntensityPatch& patch, const SphericalImages& epoch,
                                      double row, double column,
                                      const PatchMatchParameters& parameters = {});

}  // namespace tlsmon::keypoints
