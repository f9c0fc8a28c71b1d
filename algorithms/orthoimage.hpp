#pragma once
// The orthoimage of a planar part of a scan: the intensity of the points near a plane,
// projected orthogonally onto it and resampled on a regular grid of the plane's own
// coordinates. Two epochs' orthoimages of one face differ by the face's movement within
// the plane, which image correlation measures (image_correlation.hpp).
//
// Resampling: a Gaussian-weighted average of the points around each pixel centre (the
// Nadaraya–Watson estimator with a Gaussian kernel of standard deviation σ_s):
//   I(p) = Σᵢ wᵢ Iᵢ / Σᵢ wᵢ,   wᵢ = exp(−|qᵢ − p|² / (2 σ_s²)),
// over the points qᵢ within 3 σ_s. Unlike nearest-point or triangle interpolation, it
// gives an image that varies smoothly as the scan's sample positions slide over the
// texture between epochs: with σ_s near the point spacing it suppresses the frequencies
// near the sampling's Nyquist limit, where aliasing would otherwise move features by a
// fraction of the spacing from one epoch to the next.
#include <Eigen/Geometry>
#include <vector>

#include "algorithms/image.hpp"

namespace tlsmon {

// A plane with orthonormal in-plane axes u, v; its normal is u × v.
struct OrthoPlane {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d u = Eigen::Vector3d::UnitX();
    Eigen::Vector3d v = Eigen::Vector3d::UnitZ();
    double max_distance = 0.05;  // m: points farther from the plane are left out
};

// The grid: pixel (row r, column c) is centred at plane coordinates
// (u, v) = first_centre + pixel_size · (c, r); rows go along v, columns along u.
struct OrthoGrid {
    Eigen::Vector2d first_centre = Eigen::Vector2d::Zero();  // m
    double pixel_size = 0.005;                               // m
    Eigen::Index rows = 0, columns = 0;
    double kernel_sigma = 0.005;  // σ_s of the Gaussian weights, m
    // A pixel is empty when Σ wᵢ is below this: the default e^(−2) asks for a point within
    // 2 σ_s of its centre (or several a little farther).
    double min_weight = 0.1353352832366127;
};

struct Orthoimage {
    Image image;             // weighted mean intensity, empty pixels masked
    Eigen::ArrayXXd weight;  // Σ wᵢ per pixel
    OrthoPlane plane;
    OrthoGrid grid;

    // Plane coordinates (u, v) of a pixel centre (fractional pixels allowed).
    Eigen::Vector2d pixel_centre(double row, double column) const {
        return grid.first_centre + grid.pixel_size * Eigen::Vector2d(column, row);
    }
};

// Throws tlsmon::Error for axes that are not orthonormal, a non-positive pixel size or σ_s,
// an empty grid, or intensities not matching the points in number.
Orthoimage rasterise_orthoimage(const std::vector<Eigen::Vector3d>& xyz,
                                const std::vector<float>& intensity, const OrthoPlane& plane,
                                const OrthoGrid& grid);

}  // namespace tlsmon
