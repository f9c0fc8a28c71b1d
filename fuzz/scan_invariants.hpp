#pragma once
// What every parsed scan must satisfy, checked by the fuzz targets after a successful parse:
// every per-point array is empty or as long as xyz, and every grid cell lies in the grid.
// A violation traps (a finding), like a crash or a sanitizer report.
#include <cstddef>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon::fuzz {

inline void check_scan_invariants(const std::vector<Scan>& scans) {
    for (const auto& scan : scans) {
        if (!scan.intensity.empty() && scan.intensity.size() != scan.size()) __builtin_trap();
        if (!scan.rgb.empty() && scan.rgb.size() != scan.size()) __builtin_trap();
        if (!scan.grid) continue;
        if (scan.grid->row.size() != scan.size()) __builtin_trap();
        if (scan.grid->column.size() != scan.size()) __builtin_trap();
        for (std::size_t k = 0; k < scan.size(); ++k) {
            if (scan.grid->row[k] >= scan.grid->rows) __builtin_trap();
            if (scan.grid->column[k] >= scan.grid->columns) __builtin_trap();
        }
    }
}

}  // namespace tlsmon::fuzz
