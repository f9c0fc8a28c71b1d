#pragma once
// PLY point clouds (ascii, binary_little_endian, binary_big_endian), read by tlsmon itself.
//
// What a Scan gets: the `vertex` element's x, y, z (any numeric type; vertices with a NaN or
// infinite coordinate are "no return" and are skipped), intensity from a property named
// intensity, Intensity, scalar_Intensity or scalar_intensity (CloudCompare), colour from
// red, green and blue (8-bit as is, 16-bit by the high byte), and the `camera` element that
// PCL writes (view_px/py/pz the position, x_axis*/y_axis*/z_axis* the rows of the rotation)
// as the scanner pose, recorded, not applied. When that camera's viewportx × viewporty equals
// the vertex count and viewporty > 1, the vertices are an organised cloud in row-major order
// and keep that lattice as the scan grid. Every other element (faces, range_grid) and every
// other property, list properties included, is skipped.
//
// Intensity raw scale (as for PCD): 0..255 for uchar, 0..65535 for ushort; for other types
// 0..1 when every value lies in it, else the data's own min..max.
//
// ASCII files hold one element per line. Errors name the line (ascii) or the byte offset
// (binary); counts in the header are checked against the bytes that follow before anything
// is allocated.
#include <filesystem>
#include <string_view>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

// The one scan of the file; throws FormatError naming the file and the place.
std::vector<Scan> parse_ply(std::string_view bytes, const std::filesystem::path& path);
std::vector<Scan> read_ply(const std::filesystem::path& path);

}  // namespace tlsmon
