#pragma once
// Ground points of a campaign cloud by the cloth simulation filter (Zhang, Qi, Wan, Wang, Xie,
// Wang & Yan 2016, "An easy-to-use airborne LiDAR data filtering method based on cloth
// simulation", Remote Sensing 8(6):501), the filter the segment-based PLS study used. Seen the
// right way up: a cloth of particles on a horizontal grid is pushed up from below the cloud
// (CSF inverts the cloud and lets the cloth fall; the same thing), each particle stopping at
// the lowest point of its cell; springs between neighbours keep the cloth stiff, so it spans
// the underside of what stands on the ground (a building, an abutment, a wall) instead of
// climbing into it. A point is ground when it lies within `class_threshold` of the cloth.
//
// Why CSF and not PCL's progressive morphological filter: the study used CSF, its three
// parameters (cloth resolution, rigidness, threshold) mean something on site, and it runs on
// a raster of the cloth, linear in the points; PCL's filter opens the cloud point by point at
// every window size.
//
// The cloth: each iteration every free particle rises by g·Δt² (CSF's "gravity" and time
// step), then each spring between neighbours moves a free particle towards a fixed neighbour
// by 1 − 0.7^r of their height difference and two free ones towards each other by
// ½·(1 − 0.4^r) each (CSF's closed form of r passes moving 0.3 of the gap; r the rigidness,
// 1–3), and a particle reaching its cell's lowest point stops there for good. Cells without
// points take the nearest filled cell's along their row and column (CSF's scan-line fill).
// Slope smoothing (CSF's post-processing): a free particle next to a fixed one and within
// 0.3 m of its own cell's lowest point is set on it, spreading over the cloth.
//
// Two departures from CSF. The cloth has no inertia (CSF's Verlet step keeps each particle's
// speed): a cloth that keeps its speed overshoots into a building's footprint before the
// springs hold it, and a 10 × 10 × 8 m block's roof came out as ground (tests/algorithms/
// test_ground_filter.cpp); moved by a constant step it settles on the springs' shape. And a
// particle stops at the lowest point of its cell, where CSF takes the point nearest to it
// horizontally — under a deck or a soffit that point may lie on the structure overhead. On a
// slope β the lowest point sets the cloth up to ½·resolution·tan β below the ground (0.09 m at
// 20° and 0.5 m), inside the default threshold.
//
// What the cloth cannot tell from the ground is a low broad step: a pile cap 0.4 m high and
// 18 × 10 m wide is climbed at any resolution that still follows the terrain, and its top is
// taken as ground (measured on the simulated pier: docs/campaigns.md).
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace tlsmon::campaign {

struct GroundFilterParameters {
    double cloth_resolution = 0.5;  // m, the particles' spacing
    int rigidness = 3;              // 1 steep slopes, 2 relief, 3 flat terrain (CSF's classes)
    double class_threshold = 0.2;   // m, a point this close to the cloth is ground
    int max_iterations = 500;
    double time_step = 0.65;  // CSF's default
    bool slope_smoothing = true;
};

struct GroundClassification {
    std::vector<std::uint8_t> ground;  // per point, 1 = ground
    std::size_t ground_points = 0;
    int iterations = 0;  // of the cloth until it settled
    // The cloth: rows × columns heights (m) from `origin` (x, y) at the resolution.
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    int rows = 0, columns = 0;
    std::vector<double> cloth;
    // The cloth's height under (x, y), bilinear; NaN outside the cloth.
    double cloth_height(double x, double y, double resolution) const;
};

// Non-finite points are never ground. The result does not depend on `threads` (0: every core).
GroundClassification classify_ground(std::span<const Eigen::Vector3d> points,
                                     const GroundFilterParameters& parameters = {},
                                     unsigned threads = 0);

void validate(const GroundFilterParameters& parameters);

}  // namespace tlsmon::campaign
