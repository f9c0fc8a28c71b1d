#pragma once
// A preset's scan window narrowed to the directions around one point, on the same lattice
// of readout angles (same steps, cells at the same azimuths and elevations as in the full
// window), so that a test renders only the region it measures: the same geometry, beam and
// sampling as the full scan, in a fraction of its time, and the same noise at each cell (the
// window remembers where it lies in the scan's lattice: Scanner::first_column, first_row).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "simulator/scene.hpp"

namespace tlsmon::sim::test {

// Sets where `window`, cut out of `whole` (its azimuth_max and elevation_min on whole steps
// of its own step from whole's), starts in whole's lattice: so that it draws, cell by cell,
// the noise the whole scan would (simulator/render.cpp seeds a column by its lattice index).
inline void place_in_lattice(Scanner& window, const Scanner& whole) {
    const auto steps = [](double from, double to, double step) {
        return static_cast<std::uint32_t>(std::max(0.0, std::round((to - from) / step)));
    };
    window.first_column = whole.first_column + steps(window.azimuth_max_deg, whole.azimuth_max_deg,
                                                     window.azimuth_step_deg);
    window.first_row = whole.first_row + steps(whole.elevation_min_deg, window.elevation_min_deg,
                                               window.elevation_step_deg);
}

// Narrows `scanner` to ±half_deg (azimuth and elevation) about the direction of `point`
// (project frame) from the scanner, rounded outwards to whole steps.
inline void narrow_window(Scanner& sc, const Eigen::Vector3d& point, double half_deg) {
    constexpr double deg = 180.0 / std::numbers::pi;
    const Eigen::Vector3d d = point - sc.position;
    const double az = std::atan2(d.y(), d.x()) * deg - sc.heading_deg;
    const double el = std::atan2(d.z(), std::hypot(d.x(), d.y())) * deg;
    const double sa = sc.azimuth_step_deg, se = sc.elevation_step_deg;
    // Column 0 is at azimuth_max; row 0 at elevation_min: move those by whole steps.
    const double k_az = std::max(0.0, std::floor((sc.azimuth_max_deg - (az + half_deg)) / sa));
    const double k_el = std::max(0.0, std::floor((el - half_deg - sc.elevation_min_deg) / se));
    const double n_az = std::ceil(2.0 * half_deg / sa), n_el = std::ceil(2.0 * half_deg / se);
    const Scanner whole = sc;
    sc.azimuth_max_deg -= k_az * sa;
    sc.azimuth_min_deg = sc.azimuth_max_deg - n_az * sa;
    sc.elevation_min_deg += k_el * se;
    sc.elevation_max_deg = sc.elevation_min_deg + n_el * se;
    place_in_lattice(sc, whole);
}

}  // namespace tlsmon::sim::test
