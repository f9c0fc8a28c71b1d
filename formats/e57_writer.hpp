#pragma once
// A minimal E57 writer (ASTM E2807-11) for tests and benchmarks: one data3D scan per Scan,
// bit-packed with the default bitPackCodec, pages with CRC-32C. It writes what read_e57
// reads (cartesian or spherical coordinates, intensity, colour, row/column index, invalid
// states, pose, acquisition time) and nothing else.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

struct E57WriteOptions {
    // > 0: cartesian coordinates as ScaledInteger with this scale (metres per count);
    // 0: as Float (double precision).
    double coordinate_scale = 0.0;
    bool spherical = false;  // sphericalRange/Azimuth/Elevation (Float) instead of cartesian
    // > 0: after every n-th point also write a record with invalid state 2 (no point).
    std::uint32_t invalid_every = 0;
};

// Scan::xyz is taken in the project frame; the writer stores the points in the scanner
// frame (inverse pose) with the pose in the XML, as a scanner export would.
void write_e57(const std::filesystem::path& path, const std::vector<Scan>& scans,
               const E57WriteOptions& options = {});

}  // namespace tlsmon
