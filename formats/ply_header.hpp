#pragma once
// The header of a PLY file (Greg Turk's PLY polygon file format, as written by CloudCompare,
// PCL, MeshLab and scanner software): encoding, and the elements with their properties in
// file order.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "formats/point_values.hpp"

namespace tlsmon {

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct PlyProperty {
    std::string name;
    ValueType type = ValueType::float32;  // of the value, or of each list item
    bool is_list = false;
    ValueType count_type = ValueType::uint8;  // of a list's leading item count
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
    std::uint64_t header_line = 0;  // where it is declared, for errors

    bool has_lists() const;
    // Bytes of one binary record without lists; with lists the least it can take.
    std::size_t min_record_bytes() const;
    // Index of the scalar property named one of `names`, or -1.
    int find(std::initializer_list<std::string_view> names) const;
};

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::ascii;
    std::vector<PlyElement> elements;
    std::size_t data_offset = 0;     // first byte after the end_header line
    std::uint64_t header_lines = 0;  // lines up to and including end_header
};

// Throws FormatError "<file>:<line>: ..." for a malformed header.
PlyHeader parse_ply_header(std::string_view bytes, const std::filesystem::path& path);

}  // namespace tlsmon
