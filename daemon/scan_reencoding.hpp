#pragma once
// Re-encoding an archived scan as E57 (the archive policy, docs/retention.md): the file is
// read (its sha256 checked against the epoch's), written as E57 with the scan's grid,
// intensity, colour, pose and time (formats/e57_writer.hpp: coordinates as scaled integers of
// `resolution` metres, bit-packed), made durable, read back and compared point by point with
// what was read. Only a file that passes is kept; the original is left for the caller to
// delete once the database says so.
#include <cstdint>
#include <filesystem>
#include <string>

namespace tlsmon {

struct ReencodedScan {
    std::filesystem::path path;  // <stem>.e57 beside the original (or a free name like it)
    std::int64_t bytes = 0;
    std::string sha256;
};

// Throws Error naming the file and what failed (unreadable, another content than `sha256`,
// a point that differs by more than the resolution allows); nothing is left behind then.
ReencodedScan reencode_as_e57(const std::filesystem::path& source, const std::string& sha256,
                              double resolution);

}  // namespace tlsmon
