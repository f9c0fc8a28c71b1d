#pragma once
// ASPRS LAS 1.4 R15 writer: point data record format 6 (§2.6.6), every attribute as extra
// bytes after the 30-byte base record, described in the Extra Bytes VLR (user "LASF_Spec",
// record 4); the coordinate system as an OGC WKT VLR ("LASF_Projection", record 2112) when
// given. Uncompressed, so that any LAS 1.4 reader opens it.
#include <filesystem>

#include "formats/las_points.hpp"

namespace tlsmon {

// Writes to `path` + ".part", then renames: a reader never sees half a file. Throws Error
// naming the file for attributes of another length than the points, names or descriptions
// longer than 32 bytes, and write failures.
void write_las(const std::filesystem::path& path, const LasPoints& points);

}  // namespace tlsmon
