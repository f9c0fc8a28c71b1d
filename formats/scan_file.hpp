#pragma once
// Choosing the reader for a scanner export by its name and first bytes: one table of
// formats (name, extensions, magic bytes, parse function) in scan_file.cpp.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

enum class ScanFormat { ptx, pts, xyz, ply, pcd, las, laz, e57, unknown };

std::string to_string(ScanFormat f);

// By extension first (case-insensitive), then by magic bytes for LAS ("LASF"), E57
// ("ASTM-E57"), PLY ("ply") and PCD ("# .PCD" or "VERSION").
ScanFormat detect_format(const std::filesystem::path& path);

// The extensions (lower case, without the dot) the ingest folder takes by default: the
// first extension of every format in the table. .txt and .asc are read as XYZ when named,
// but not taken by default: notes and logs carry those names too.
std::vector<std::string> scan_extensions();

// Every scan in the file, in file order. Throws FormatError naming file and position.
std::vector<Scan> read_scans(const std::filesystem::path& path);

// The same from the file's bytes already in memory (`path` names the file in messages and
// chooses the format by extension): the daemon parses exactly the bytes whose sha256
// identifies the epoch, and a file truncated by another process meanwhile cannot fault a
// memory map under the reader.
// Every reader's scans pass check_coordinates.
std::vector<Scan> parse_scans(std::string_view bytes, const std::filesystem::path& path);

// A point or a scanner position beyond kMaxCoordinate (format_error.hpp), or one that is
// not finite, comes from a corrupt file (a scale, an offset or a matrix of 1e300), which
// would otherwise be analysed into nonsense. Throws FormatError naming the file, the scan and the
// first such point.
void check_coordinates(const std::vector<Scan>& scans, const std::filesystem::path& path);

// Every scan's points in one list, in file order (a campaign's cloud; a reference taken as
// points). Throws Error naming `source` when there are none.
std::vector<Eigen::Vector3d> all_points(const std::vector<Scan>& scans, const std::string& source);

}  // namespace tlsmon
