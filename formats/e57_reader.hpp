#pragma once
// ASTM E2807 (E57) reader: every data3D scan of the file as one Scan, in the project
// frame (pose applied), with intensity, colour and the row/column grid where present.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "core/scan.hpp"

namespace tlsmon {

// Throws FormatError naming the file and the byte offset for a damaged or unsupported file.
std::vector<Scan> read_e57(const std::filesystem::path& path);

// The same from bytes in memory; `source` names them in Scan::source and in errors.
std::vector<Scan> parse_e57(const char* data, std::size_t size,
                            const std::filesystem::path& source);

// The acquisitionStart of the first scan that has one, in UTC, reading only the file
// header and the XML section (not the points): for ingest, which needs the time early.
std::optional<double> read_e57_acquired_utc(const std::filesystem::path& path);

}  // namespace tlsmon
