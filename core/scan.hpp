#pragma once
// One scan as read from a scanner export: the in-memory type every reader produces and
// every later stage consumes.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tlsmon {

// Structured scans (PTX, gridded E57) keep the scanner's row/column lattice: neighbours in
// the grid are neighbours on the surface, which the spherical-image analyses rely on.
// Cells that no point references are empty (no return).
struct ScanGrid {
    std::uint32_t rows = 0;
    std::uint32_t columns = 0;
    std::vector<std::uint32_t> row;     // per point
    std::vector<std::uint32_t> column;  // per point

    std::uint64_t cells() const { return std::uint64_t{rows} * columns; }
    // More cells than kMaxCellsPerPoint a point, plus kSlack: what works on the grid holds a
    // few bytes a cell (depth discontinuities, plane detection), so a grid a damaged file
    // claims must not be taken at its word. A scanner's grid, cut to the cells its returns
    // occupy, has returns in a large share of them (the `pier` preset's 74 %), sky and water
    // left empty; one filled less than 1/32 is not taken as a grid (formats/e57_reader.cpp
    // refuses it).
    bool too_sparse() const { return cells() > kMaxCellsPerPoint * row.size() + kSlack; }
    static constexpr std::uint64_t kMaxCellsPerPoint = 32;
    static constexpr std::uint64_t kSlack = std::uint64_t{1} << 24;
};

using Rgb8 = std::array<std::uint8_t, 3>;

struct Scan {
    std::string source;  // file path, and "#k" for the k-th scan of a multi-scan file
    std::string name;    // the scan's own name where the format has one

    // Coordinates in the project frame: the format's scanner->project transform applied
    // exactly as the format defines it. `pose` keeps that transform.
    std::vector<Eigen::Vector3d> xyz;
    Eigen::Affine3d pose = Eigen::Affine3d::Identity();  // scanner -> project frame

    // Intensity normalised to 0..1 (empty when the file has none); the file's raw value is
    // intensity_raw_min + i * (intensity_raw_max - intensity_raw_min).
    std::vector<float> intensity;
    double intensity_raw_min = 0.0;
    double intensity_raw_max = 1.0;

    std::vector<Rgb8> rgb;  // empty when the file has no colour; 16-bit colour is scaled to 8

    std::optional<ScanGrid> grid;

    // Acquisition time, seconds since 1970-01-01T00:00:00Z, when the file says it.
    std::optional<double> acquired_utc;

    std::size_t size() const { return xyz.size(); }
    Eigen::Vector3d scanner_position() const { return pose.translation(); }
};

}  // namespace tlsmon
