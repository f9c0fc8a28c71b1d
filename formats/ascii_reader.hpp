#pragma once
// PTS and XYZ ASCII point lists (unstructured, no pose).
//
// One point per line: `x y z`, `x y z i`, `x y z r g b` or `x y z i r g b`, values
// separated by spaces, tabs or commas; blank lines and comment lines starting with `#` or
// `//` are skipped. Every point line of a block has the same number of values.
//
// PTS: a line holding a single integer is a point count; the points that follow must match
// it. Several count + points blocks give several scans. Intensity is -2048..2047
// (Leica PTS), normalised to 0..1 with that raw scale recorded.
//
// XYZ: no count line. Intensity "as given": the raw scale is the first of 0..1, 0..255,
// 0..65535 that holds every value of the file (a fixed scale, so that epochs written by
// the same exporter compare); beyond 65535 or below 0 it is the file's own min..max.
#include <filesystem>
#include <string_view>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

std::vector<Scan> read_pts(const std::filesystem::path& path);
std::vector<Scan> read_xyz(const std::filesystem::path& path);

// The same from a buffer in memory; `file` names it in Scan::source and in errors.
std::vector<Scan> parse_pts(std::string_view text, const std::filesystem::path& file);
std::vector<Scan> parse_xyz(std::string_view text, const std::filesystem::path& file);

}  // namespace tlsmon
