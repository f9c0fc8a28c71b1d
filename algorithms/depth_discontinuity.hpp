#pragma once
// The points of a structured scan at a depth discontinuity: where the surface seen breaks off
// (a face's edge, the foot of a wall, an object in front of another). A beam there may
// straddle the edge, and a phase-based rangefinder returns the power-weighted blend of the
// ranges it meets, a "mixed pixel" between the two surfaces (Hebert & Krotkov 1992; Tang,
// Huber & Akinci 2007 compare detectors). Small blends lie within a plane's noise clip, but
// which beams straddle an edge changes with the grid's phase on it from epoch to epoch.
//
// Marked: a point next to a cell of the grid without a return (nothing there, or a return too
// weak to keep, as from a grazing face: its beams may still blend in a little of it), or
// whose range's second difference along an axis of the grid, r(i−1) − 2·r(i) + r(i+1), is
// beyond `jump` and beyond half the larger of the two first differences (a step, not a slope:
// a face seen at 87° on a 0.1° grid has second differences of 0.1 m along its whole width,
// but first differences of 1.5 m); and, with `with_neighbours`, the points next to those in
// the grid, as a beam one step from the edge straddles it too when the footprint is as wide as the
// step (at 50 m the pier preset's 1/e² radius, 9 mm, and step, 11 mm: the point next to a blend 1.9
// cm behind the face was itself 1.1 mm behind it). Along a plane the ranges are smooth even at
// grazing incidence (the second difference of r = d / cos θ over a step Δθ is r·Δθ²·(1 + 2 tan² α),
// 0.2 mm at 50 m, 80° and 0.013°), while at an edge it is the step between the surfaces; the noise
// adds √6·σ_r. Points on the grid's own border are tested along the other axis alone. Without a
// grid (an unstructured scan) no point is marked.
#include <cstdint>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

// m: the `jump` of the stages that leave such points out (M3C2, PB-M3C2): a surface this far
// behind (their search depth's worth) is not the one measured. Smaller steps are a surface's
// own relief (rough ground seen at 65° steps by centimetres from beam to beam), which must not
// be thinned by its peaks and pits; at the pier's corner the step to the grazing west face is
// some 0.3 m a column.
constexpr double kMixedPixelJump = 0.10;

// Per point of `scan`, 1 at a depth discontinuity; empty when the scan has no grid. On
// `threads` threads (0: every core); the result does not depend on them. Without
// `with_neighbours` the points next to a marked one are not marked as well.
std::vector<std::uint8_t> depth_discontinuities(const Scan& scan, double jump, unsigned threads = 0,
                                                bool with_neighbours = true);

}  // namespace tlsmon
