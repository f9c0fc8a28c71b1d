#pragma once
// Sub-pixel refinement of a match by least-squares image matching (Grün 1985, "Adaptive
// least squares correlation: a powerful image matching technique", S. Afr. J. Photogramm.
// 14(3), 175–187; here with a shift and a linear radiometric model only): a square patch of
// the reference's intensity around a pixel is sought in the epoch's intensity image,
//   E(r + i + Δr, c + j + Δc) ≈ g · P(i, j) + o,
// solved for (Δr, Δc, g, o) by Gauss–Newton, E interpolated by its cubic B-spline
// (cubic_bspline.hpp: Keys' cubic convolution pulled every patch of a face by up to 0.01
// pixel, the same way, by its phase error at the lattice's fraction; docs/keypoints.md, "The
// lattice's phase") and the Jacobian from the reference patch's gradient (the epoch's noise
// kept out of it).
//
// Why: a detector's keypoint is placed to a tenth of a pixel at best; the patch's position
// is found from all its pixels, and the reference's end is a pixel centre (an exact return,
// nothing interpolated).
//
// Both images are first smoothed by a Gaussian of σ = prefilter pixels (Pan 2013, "Bias
// error reduction of digital image correlation using Gaussian pre-filtering", Opt. Lasers
// Eng. 51(10), 1161–1167). A scan sampled at about its footprint is aliased: its detail
// finer than two pixels is fixed to the scanner's lattice, not to the surface. When the
// lattice drifts over the surface by a fraction of a pixel (the scanner turns by
// arcseconds), that detail pulls every patch's shift the same way, and no interpolant can
// undo it; the prefilter takes the aliased band's weight out of the adjustment. On the
// simulated `pier` without deformation and with the true registration, the refined matches
// showed −0.2 to −1.1 mm along the wall in every zone without it (bilinear or cubic), −0.04
// to −0.07 mm with σ = 1.5 pixels (docs/keypoints.md).
#include <cstddef>
#include <optional>
#include <vector>

#include "algorithms/cubic_bspline.hpp"
#include "algorithms/keypoints/spherical_image.hpp"

namespace tlsmon::keypoints {

// The reference's intensity at the (2·radius + 1)² pixels around (row, column), row-major.
struct IntensityPatch {
    int row = 0, column = 0;  // the centre pixel
    int radius = 0;
    std::vector<float> values;
};

// The intensity image the refinement works on: smoothed by a Gaussian of σ pixels over the
// pixels with a return (normalised convolution: an empty pixel neither darkens its
// neighbours nor is filled; it stays empty); σ ≤ 0: the intensity as it is.
Image gaussian_prefiltered(const SphericalImages& images, double sigma);

// Nothing when a pixel of the patch lies outside the image or has no return.
std::optional<IntensityPatch> intensity_patch(const Image& intensity, int row, int column,
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

// Starting from (row, column) in the epoch's image (its cubic B-spline: bspline_image of the
// prefiltered intensity). Nothing when the patch runs into an empty pixel or the image's
// edge, does not converge, moves too far, or correlates poorly.
std::optional<PatchMatch> match_patch(const IntensityPatch& patch, const BSplineImage& epoch,
                                      double row, double column,
                                      const PatchMatchParameters& parameters = {});

}  // namespace tlsmon::keypoints
