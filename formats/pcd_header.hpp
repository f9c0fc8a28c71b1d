#pragma once
// The header of a PCD file (PCL's Point Cloud Data format, v0.7): fields with their size,
// type and count, the cloud's width × height, the viewpoint, and how the data is stored.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "formats/point_values.hpp"

namespace tlsmon {

enum class PcdData { ascii, binary, binary_compressed };

struct PcdField {
    std::string name;
    ValueType type = ValueType::float32;
    std::size_t count = 1;   // values per point (COUNT)
    std::size_t offset = 0;  // bytes before it in a point record
    std::size_t bytes() const { return value_size(type) * count; }
};

struct PcdHeader {
    std::vector<PcdField> fields;
    std::uint64_t width = 0;
    std::uint64_t height = 1;
    Eigen::Vector3d viewpoint_origin = Eigen::Vector3d::Zero();
    Eigen::Quaterniond viewpoint_orientation = Eigen::Quaterniond::Identity();
    PcdData data = PcdData::ascii;
    std::size_t data_offset = 0;     // first byte after the DATA line
    std::uint64_t header_lines = 0;  // lines up to and including DATA
    std::size_t record_bytes = 0;    // one point, all fields

    std::uint64_t points() const { return width * height; }
    // The field named one of `names`, or nullptr.
    const PcdField* find(std::initializer_list<std::string_view> names) const;
    // Values per point (the sum of the counts): the tokens of an ASCII data line.
    std::size_t values_per_point() const;
};

// Throws FormatError "<file>:<line>: ..." for a malformed or incomplete header.
PcdHeader parse_pcd_header(std::string_view bytes, const std::filesystem::path& path);

}  // namespace tlsmon
