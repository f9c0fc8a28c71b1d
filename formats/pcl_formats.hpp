#pragma once
// PLY and PCD exports, read with PCL's io (the only place that includes PCL; see
// pcl_adapter.cpp). Free of PCL headers so that callers compile fast.
//
// What a Scan gets: x, y, z (float or double fields; points with a NaN or infinite
// coordinate are PCL's "no return" and are skipped), intensity when a field "intensity"
// (or CloudCompare's "scalar_Intensity") exists, colour from a packed "rgb"/"rgba" field,
// and the sensor viewpoint (PCD VIEWPOINT, PLY camera element) as the scanner pose. An
// organised cloud (height > 1) keeps its lattice as the scan grid.
//
// Intensity raw scale: 0..255 for uint8 fields, 0..65535 for uint16 fields; for other
// types 0..1 when every value lies in it, else the data's own min..max.
#include <filesystem>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

// Throw FormatError naming the file when PCL cannot read it or a field is unusable.
std::vector<Scan> read_ply(const std::filesystem::path& path);
std::vector<Scan> read_pcd(const std::filesystem::path& path);

}  // namespace tlsmon
