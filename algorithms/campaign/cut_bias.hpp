#pragma once
// The bias a segment's own cut puts into its registration, and its bound.
//
// A segment is the part of a surface its measured points fall in: where the surface goes on
// beyond the segment (the ground filter's cut along a face's foot, a change of verticality
// class, a gap the clustering does not bridge), which side a point lands on depends on its
// noise. A scanner's noise lies along its pulse, e = ε·u, so the part along the surface
// across the cut, ε·u_b, and the part along the surface's normal, ε·u_n, err together: the
// points kept are those whose noise moved them inwards, and their mean offset from the
// surface is biased. Summed over a straight cut of length L through points of density ρ,
// ρ·L·∫ E[ε·u_n·1(s + ε·u_b > 0)] ds = ρ·L·u_n·u_b·σ²; over the segment's ρ·A points,
//     bias = (L/A)·u_n·u_b·σ²  ≤  (L/A)·σ_n·√(σ² − σ_n²),
// with σ the range noise and σ_n = σ·|u_n| the noise along the normal (u_n² + u_b² ≤ 1).
// L/A is estimated from the share f of the segment's points that have a point of something
// else within a distance d: the band of width d along the cuts holds ρ·L·d points, so
// L/A = f/d. A true edge of the surface, with nothing beyond it, is no cut and is not
// counted. (Seen on the simulated pier's pile cap: a 0.4 m face cut at 0.2 m by the ground
// filter, 20 mm noise along pulses from 1.5 m above, read 1–2 mm off with σ 0.4 mm.)
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace tlsmon::campaign {

// Per label 0 … labels − 1: the share of its points (at most `samples` of them, taken evenly)
// with a point of another label (−1 included) within `distance`. NaN for a label without
// points. The result does not depend on `threads` (0: every core).
std::vector<double> cut_fractions(std::span<const Eigen::Vector3d> points,
                                  std::span<const std::int32_t> label, std::size_t labels,
                                  double distance, std::size_t samples, unsigned threads = 0);

// The bound above, m: (f/d)·σ_n·√(σ² − σ_n²), σ_n taken at most σ.
double cut_bias_bound(double fraction, double distance, double range_sigma, double normal_sigma);

}  // namespace tlsmon::campaign
