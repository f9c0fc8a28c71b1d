#pragma once
// Choosing the reader for a scanner export by its name and first bytes.
#include <filesystem>
#include <string>
#include <vector>

#include "formats/scan.hpp"

namespace tlsmon {

enum class ScanFormat { ptx, pts, xyz, ply, pcd, las, laz, e57, unknown };

std::string to_string(ScanFormat f);

// By extension first (case-insensitive), then by magic bytes for LAS ("LASF"), E57
// ("ASTM-E57"), PLY ("ply\n") and PCD ("# .PCD").
ScanFormat detect_format(const std::filesystem::path& path);

// Every scan in the file, in file order. Throws FormatError naming file and position.
std::vector<Scan> read_scans(const std::filesystem::path& path);

}  // namespace tlsmon
