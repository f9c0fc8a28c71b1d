#pragma once
// The XML section of an E57 file (ASTM E2807-11 §9-§10) reduced to what the reader needs:
// per data3D scan its name, pose, limits, index bounds, acquisition time and the
// compressed vector of points with its prototype. Images, grouping schemes and foreign
// extension elements are skipped.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "formats/e57_pages.hpp"

namespace tlsmon {

enum class E57FieldType { integer, scaled_integer, float_single, float_double };

// One terminal element of a prototype; each owns one bytestream (E2807 §10.6).
struct E57Field {
    std::string name;  // e.g. "cartesianX", "nor:normalX"; nested ones as "a/b"
    E57FieldType type = E57FieldType::float_double;
    std::int64_t minimum = 0;  // Integer / ScaledInteger: raw bounds
    std::int64_t maximum = 0;
    double scale = 1.0;  // ScaledInteger: value = raw * scale + offset
    double offset = 0.0;
    double float_minimum = 0.0;  // Float: declared bounds (not used for decoding)
    double float_maximum = 0.0;
    std::uint64_t xml_byte = 0;  // physical file offset of the element, for errors

    // Bits per value in the bytestream: Float is stored whole, integers in
    // ceil(log2(maximum - minimum + 1)) bits (E2807 §10.6.2, bitPackCodec).
    unsigned bits() const;
    // Value range as the file declares it (scaled for ScaledInteger).
    double declared_minimum() const;
    double declared_maximum() const;
};

struct E57CompressedVector {
    std::uint64_t file_offset = 0;  // physical offset of the section header
    std::uint64_t record_count = 0;
    std::vector<E57Field> fields;  // prototype terminals, in bytestream order
    std::uint64_t xml_byte = 0;
};

struct E57Range {
    double minimum = 0.0;
    double maximum = 0.0;
};

struct E57IndexBounds {
    std::int64_t row_minimum = 0, row_maximum = 0;
    std::int64_t column_minimum = 0, column_maximum = 0;
};

struct E57ScanInfo {
    std::string name;
    Eigen::Affine3d pose = Eigen::Affine3d::Identity();
    std::optional<E57Range> intensity_limits;
    std::optional<E57Range> color_limits[3];  // red, green, blue
    std::optional<E57IndexBounds> index_bounds;
    std::optional<double> acquisition_start_gps;  // seconds since 1980-01-06T00:00:00 GPS
    E57CompressedVector points;
    std::uint64_t xml_byte = 0;
};

// Parses the XML section; errors name the file and the physical byte of the element.
std::vector<E57ScanInfo> parse_e57_xml(const E57Pages& pages, std::string_view xml);

}  // namespace tlsmon
