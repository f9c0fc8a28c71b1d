#pragma once
// The planes of a structured scan, found in its image matrix (the rows and columns of the
// scanner's grid): the plane-based registration's observations (plane_registration.hpp).
//
// 1. Recursive split: a block of the grid (first the whole grid in tiles of `tile` cells) is
//    fitted with a plane (plane_fit.hpp). It is planar when its points' scatter about the
//    plane agrees with the scanner's stochastic model: s² ≤ σ̄²·χ²(N − 3, 1 − α)/(N − 3),
//    σ̄² the mean over its points of
//        σ² = (σ_r·cos β)² + (r·σ_θ·sin β)² + flatness²,   σ_r = a + b·r,
//    β the incidence angle of each point's beam on the plane: the range noise projected on
//    the normal, the direction's noise across it, and the surface's own departure from a
//    plane. A planar block is kept; one that is not is split in four, down to `min_cells`
//    rows or columns.
// 2. Merging: kept blocks that touch in the grid merge when their planes are statistically
//    equal: the difference w (the tilt between their normals towards the first one's axes
//    and the second centroid's distance from the first plane) against its covariance,
//    wᵀ·Σ_ww⁻¹·w ≤ χ²(3, 1 − merge_alpha) (plane_registration.hpp, with R = I, t = 0). A
//    merged group is fitted again on all its points.
// 3. Significance: a plane (merged or alone) is kept when its normal is significant, the σ
//    of its tip below `max_normal_sigma_arcsec`. Tested after the merge, so that a small
//    face (a foundation's 0.4 m showing above the floor, a low wall) whose blocks are each
//    too small to fix a normal is found as the sum of them.
// 4. Edges: the points within `edge_cells` of a plane's edge in the grid (a cell of another
//    plane or none beside them, along the row or the column) leave it, and it is fitted
//    again on its inner points.
#include <cstdint>
#include <vector>

#include "algorithms/registration/plane_fit.hpp"
#include "core/scan.hpp"
#include "core/scanner_noise.hpp"

namespace tlsmon::registration {

struct PlaneDetectionParams {
    ScannerNoise noise;                   // the scanner's stochastic model
    double flatness = 0.001;              // m, the surface's own departure from a plane
    double alpha = 0.01;                  // the planarity test's level
    std::uint32_t tile = 256;             // cells per side of the first blocks
    std::uint32_t min_cells = 8;          // a block is not split below this many rows or columns
    std::size_t min_points = 50;          // fewer points in a block: no plane
    double max_normal_sigma_arcsec = 60;  // larger: the block's normal is not significant
    double merge_alpha = 0.001;           // the test of two touching planes' equality
    // A point this many cells or fewer from the plane's edge in the grid is left out of the
    // final fit: at an edge the beam's footprint straddles the plane and what is behind it
    // (mixed returns), which tilts a narrow face by minutes of arc.
    std::uint32_t edge_cells = 1;
};

struct DetectedPlane {
    FittedPlane plane;                  // in the scan's frame (the scan's coordinates)
    std::vector<std::uint32_t> points;  // indices into the scan
    std::uint32_t row_min = 0, row_max = 0, column_min = 0, column_max = 0;  // grid extent
    std::size_t blocks = 0;  // the split's blocks merged into it
};

// The planes of `scan`, largest (most points) first. The scanner is at the scan's
// `scanner_position()`. Throws tlsmon::Error for a scan without a grid.
std::vector<DetectedPlane> detect_planes(const Scan& scan, const PlaneDetectionParams& params = {});

// The test of two planes' equality: wᵀ·Σ_ww⁻¹·w of their difference (header), ~ χ²(3) when
// both fit the same plane.
double plane_difference_statistic(const FittedPlane& a, const FittedPlane& b);

}  // namespace tlsmon::registration
