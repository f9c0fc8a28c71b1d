#pragma once
// Rendering one epoch's structured scan: rows × columns of beams cast from the disturbed
// scanner pose into the scene, measured with noise, returned as a Scan with its grid and the
// nominal (header) pose.
//
// Grid: column 0 is the first azimuth of the scan; columns advance clockwise seen from
// above (azimuth decreasing), as a TLS head turns. Row 0 is the lowest elevation; rows go
// up. Every point is stored with its row and column; empty cells (sky, out of range, too
// weak a return) have no point.
//
// Measurement model per cell (nominal readout angles φ, e from the grid):
//   beam direction   = d(φ + ε_φ, e + ε_e), ε ~ N(0, σ_angle)     encoder / beam jitter
//   footprint        = sub-rays about the beam (footprint.hpp); r_true is their
//                      power-weighted range, the intensity their weighted return
//   measured range   = r_true · n_true/n_setting + N(0, σ_r²)   atmosphere.hpp; σ_r from
//                      range_noise.hpp (of r_true)
//   point (scanner)  = measured range · d(φ, e)                    computed from the readout
//   intensity        = Σ wₖ albedoₖ · exp(−rₖ / r_att) · |cos αₖ| + N(0, σ_i), clamped 0..1
// and a cell whose noise-free intensity is below `min_return` has no point. With
// `beam.footprint` off the footprint is the central ray alone.
#include <array>
#include <cstdint>
#include <vector>

#include "core/scan.hpp"
#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

// Largest grid rendered: memory grows by about 120 bytes per cell (points, grid indices,
// PTX text), so 50 M cells need about 6 GB.
constexpr std::uint64_t max_scan_cells = 50'000'000;

struct GridShape {
    std::uint32_t rows = 0, columns = 0;
};
GridShape grid_shape(const Scanner& scanner);

// Readout angles of a cell, radians, scanner frame.
double cell_azimuth(const Scanner& scanner, std::uint32_t column);
double cell_elevation(const Scanner& scanner, std::uint32_t row);

struct RenderedScan {
    Scan scan;  // xyz through the nominal pose (what a reader gets from the header)
    PoseError pose_error;
    int epoch = 0;
    double hours = 0.0;
    std::uint64_t mixed_pixels = 0;  // points whose footprint straddled surfaces (footprint.hpp)
    // Per point (scan order): the surface (ray_cast.hpp Surface) that returned most of the
    // footprint's power, and the number of points per surface.
    std::vector<std::uint8_t> surface;
    std::array<std::uint64_t, kSurfaceKinds> points_by_surface{};
};

// Renders the epoch of `conditions` on `threads` threads (the result does not depend on the
// thread count). Throws tlsmon::Error for a grid over max_scan_cells.
RenderedScan render_epoch(const Site& site, const EpochConditions& conditions,
                          unsigned threads = 2);
// Epoch `epoch`, `hours` after a first epoch at kDefaultStartUtc (epoch_conditions.hpp).
RenderedScan render_epoch(const Site& site, int epoch, double hours, unsigned threads = 2);

// The scanner as it runs detail scan `d`: the overview's station, pose and limits, the
// detail's window and step.
Scanner detail_scanner(const Scanner& overview, const DetailScan& d);

// Detail scan `detail` (index into site.scanner.details) of the same epoch: the same pose
// error, scene and air as the overview, its own noise stream; named "<station>-<name>".
RenderedScan render_detail(const Site& site, std::size_t detail, const EpochConditions& conditions,
                           unsigned threads = 2);

}  // namespace tlsmon::sim
