#pragma once
// Leica PTX (ASCII, structured) reader.
//
// Per scan a 10-line header: columns, rows, scanner position (3 numbers), scanner X, Y, Z
// axes (3 lines of 3), then a 4x4 matrix in row-vector form, p' = [x y z 1]·M, with the
// translation on its last line. Then columns × rows point lines, column by column: within
// a column the k-th line is grid row k (Scan::grid row k, column = line index / rows).
// Point lines are `x y z i`, `x y z i r g b` or `x y z i r g b nx ny nz` (the 10-column
// form adds a normal, which is not kept). A cell written `0 0 0 ...` had no return: it is
// a grid cell but not a point. Several scans may follow each other.
//
// Intensity is 0..1 in PTX; files whose intensities leave 0..1 are taken as the integer
// scale -2047..2048 some exporters write, normalised to 0..1 with that raw scale recorded.
#include <filesystem>
#include <string_view>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

// Every scan of the file; throws FormatError naming the file and line.
std::vector<Scan> read_ptx(const std::filesystem::path& path);

// The same from a buffer in memory; `file` names it in Scan::source and in errors.
std::vector<Scan> parse_ptx(std::string_view text, const std::filesystem::path& file);

}  // namespace tlsmon
