#pragma once
// A zone's median change over its area from its patches (docs/pbm3c2.md, "The zone median
// over the area").
//
// The patches' distances are taken at their centroids; the median of those alone is one
// patch's value, and where the change varies across the zone by more than the patches' noise
// (a face in bending) the values of a row of patches form a cluster: the median then steps
// from cluster to cluster with the count on either side (a strip of small patches at one edge
// moves it by half a row), while the zone's change over its area lies between them. Here
// every footprint cell of every patch is one vote, with the change at its place,
//   d_c = d_k + ĝᵀ(x_c − x_k),
// d_k the patch's distance at x_k, x_c the cell's centre, and ĝ the zone's gradient of the
// change: the least-squares plane of the d_k over the x_k, weighted by the patches' cells,
// fitted again without the patches more than 3.5 robust σ (kMadToSigma·MAD) from it. The
// gradient is the zone's, not each patch's own (the slope between its two planes): over a
// patch of 1 m the fits' slopes err by tenths of a millimetre, more than a bending changes
// it there. In a direction the centroids do not span (the face's normal) ĝ has no component.
// The median of the d_c is the zone's median over its area when its change is linear across
// a patch; its sampling variance is median_sampling_variance over members that are the
// patches, each erring as one over its cells (algorithms/m3c2/zone_uncertainty.hpp).
// Each patch's cells lie on its own grid: where two neighbours' footprints overlap at a seam,
// that strip votes twice, once with each patch's change (symmetric about the seam; not
// corrected).
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace tlsmon::patches {

struct PatchChange {
    Eigen::Vector3d at = Eigen::Vector3d::Zero();  // where the distance was taken
    double distance = 0;                           // m
    double sampling_sigma = 0;                     // m, the fits' part of its σ
    std::vector<Eigen::Vector3d> cells;            // its footprint cells' centres
};

struct ArealMedian {
    double value = std::numeric_limits<double>::quiet_NaN();  // m
    double sampling_variance = 0;                             // m²
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();       // ĝ, m per m
    std::size_t cells = 0;
};

// NaN without a cell. Throws tlsmon::Error for a non-finite distance or position, or a
// negative or non-finite σ.
ArealMedian areal_median(std::span<const PatchChange> patches);

}  // namespace tlsmon::patches
