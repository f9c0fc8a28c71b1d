#pragma once
// PCD point clouds (PCL's Point Cloud Data format v0.7; DATA ascii, binary and
// binary_compressed), read by tlsmon itself.
//
// What a Scan gets: x, y, z (any TYPE/SIZE; the first value when COUNT > 1; points with a
// NaN or infinite coordinate are PCL's "no return" and are skipped), intensity from a field
// named intensity, Intensity, scalar_Intensity or scalar_intensity, colour from a packed
// 4-byte "rgb" or "rgba" field (0x00RRGGBB, alpha dropped), and VIEWPOINT as the scanner
// pose (recorded, not applied). An organised cloud (HEIGHT > 1) keeps its WIDTH × HEIGHT
// lattice, row-major, as the scan grid. Other fields (and padding fields "_") are skipped.
//
// Intensity raw scale (as for PLY): 0..255 for U1 fields, 0..65535 for U2 fields; for other
// types 0..1 when every value lies in it, else the data's own min..max.
//
// binary_compressed is two uint32 sizes then LZF data that expands to each field's values
// for all points in turn (PCL's pcl::PCDWriter::writeBinaryCompressed).
#include <filesystem>
#include <string_view>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

// The one scan of the file; throws FormatError naming the file and the line or byte.
std::vector<Scan> parse_pcd(std::string_view bytes, const std::filesystem::path& path);
std::vector<Scan> read_pcd(const std::filesystem::path& path);

}  // namespace tlsmon
