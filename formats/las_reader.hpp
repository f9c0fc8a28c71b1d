#pragma once
// ASPRS LAS 1.0–1.4 reader (uncompressed), point data record formats 0–10.
//
// What a Scan gets from a LAS file:
// - xyz: the record's integers with the header's scale and offset applied
//   (LAS 1.4 R15 §2.4: Xcoordinate = Xrecord * Xscale + Xoffset); identity pose.
// - intensity: the uint16 field over the fixed raw scale 0..65535 (the spec asks writers
//   to normalise to 16 bits). Files that hold 8-bit values (the LAS 1.0–1.2 samples,
//   0–254) therefore read as small intensities; a per-file guess would make epochs of one
//   station incomparable.
// - rgb (formats 2, 3, 5, 7, 8, 10): 16-bit colour to 8 bits by the high byte, which
//   inverts both v*256 and v*257 up-scaling; colour that never exceeds 255 is 8-bit colour
//   stored in 16-bit fields and kept as is.
// - acquired_utc: the earliest GPS time, when the global encoding says it is Adjusted
//   Standard GPS time (GPS seconds − 1e9); GPS week time has no date and gives none.
// VLRs and extended VLRs are skipped but bounds-checked; extra bytes after the format's
// base record are skipped (read_las_points reads them). LAZ and COPC (compressed) are rejected with
// a clear message.
#include <cstddef>
#include <filesystem>
#include <vector>

#include "core/scan.hpp"
#include "formats/las_points.hpp"

namespace tlsmon {

// The one scan of a LAS file. Throws FormatError naming the file and the byte offset.
std::vector<Scan> read_las(const std::filesystem::path& path);

// The same from a LAS file already in memory; `source` names it in errors and Scan::source.
Scan parse_las(const char* data, std::size_t size, const std::filesystem::path& source);

// The points with the attributes of the Extra Bytes VLR (every scalar type, as doubles with
// the descriptor's scale and offset applied) and the OGC WKT VLR: what `tlsmon export`
// wrote, read back by the same checks as a scan.
LasPoints read_las_points(const std::filesystem::path& path);
LasPoints parse_las_points(const char* data, std::size_t size, const std::filesystem::path& source);

}  // namespace tlsmon
