#pragma once
// Choosing the reader for a scanner export by its name and first bytes.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

enum class ScanFormat { ptx, pts, xyz, ply, pcd, las, laz, e57, unknown };

std::string to_string(ScanFormat f);

// By extension first (case-insensitive), then by magic bytes for LAS ("LASF"), E57
// ("ASTM-E57"), PLY ("ply\n") and PCD ("# .PCD").
ScanFormat detect_format(const std::filesystem::path& path);

// Every scan in the file, in file order. Throws FormatError naming file and position.
std::vector<Scan> read_scans(const std::filesystem::path& path);

// The same from the file's bytes already in memory (`path` names the file in messages and
// chooses the format by extension): the daemon parses exactly the bytes whose sha256
// identifies the epoch, and a file truncated by another process meanwhile cannot fault a
// memory map under the reader. PLY and PCD are read from `path` by PCL itself.
std::vector<Scan> parse_scans(std::string_view bytes, const std::filesystem::path& path);

}  // namespace tlsmon
