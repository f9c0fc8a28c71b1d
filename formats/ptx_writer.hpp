#pragma once
// Leica PTX writer (the simulator's export format; the layout is the one read_ptx reads).
//
// Header: columns, rows, scanner position, scanner X, Y, Z axes (one line each), then the
// scanner -> project transform as a 4x4 matrix in row-vector form p' = [x y z 1]·M: the
// first three lines are the axes again, the last line is the translation followed by 1.
// Then columns × rows lines `x y z i`, column by column; within a column line k is grid
// row k. Points are in the scanner's own frame (Scan::pose⁻¹ applied to Scan::xyz);
// a cell without a point is written `0 0 0 0.5`. Header numbers are written exactly
// (shortest round-trip form), point coordinates with a fixed number of decimals.
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>

#include "core/scan.hpp"

namespace tlsmon {

struct PtxWriteOptions {
    int coordinate_decimals = 6;  // as Leica Cyclone writes; 1 µm
    int intensity_decimals = 6;
};

// The whole file as text. Throws tlsmon::Error if the scan has no grid, if grid and points
// disagree in size, or if a cell is out of the grid or holds two points.
std::string ptx_text(const Scan& scan, const PtxWriteOptions& options = {});

// Writes ptx_text(scan) to `path` (replaced). Throws tlsmon::Error naming the file when
// the write fails.
void write_ptx(const Scan& scan, const std::filesystem::path& path,
               const PtxWriteOptions& options = {});

}  // namespace tlsmon
