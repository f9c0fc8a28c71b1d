#pragma once
// Points with named per-point attributes as LAS 1.4 carries them: the coordinates in the
// point records, every attribute as an "extra bytes" field described in the Extra Bytes VLR
// (ASPRS LAS 1.4 R15 §2.5.3, Table 24). What `tlsmon export` writes and read back by
// read_las_points (formats/las_reader.hpp).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tlsmon {

struct LasAttribute {
    // The Extra Bytes data_type codes this writer uses (R15 Table 25).
    enum class Type : std::uint8_t { u8 = 1, u32 = 5, i32 = 6, f32 = 9, f64 = 10 };
    std::string name;         // at most 32 bytes, e.g. "m3c2_distance_m"
    std::string description;  // at most 32 bytes, e.g. "M3C2 distance along n, m"
    Type type = Type::f32;
    std::vector<double> values;  // one per point; NaN (floats only): no value there
};

struct LasPoints {
    std::vector<Eigen::Vector3d> xyz;  // m
    std::vector<LasAttribute> attributes;
    std::string wkt;  // the coordinate system as OGC WKT; "" when the site names none
    // Every point's GPS time (Adjusted Standard GPS time, R15 §2.4 global encoding bit 0):
    // the acquisition of the epoch the values belong to, UTC seconds.
    std::optional<double> acquired_utc;
};

// X = Xrecord · scale + offset (R15 §2.4). The step is 1 µm where a 32-bit integer spans the
// points around the offset (±2147 m), coarser by decades beyond; the offset is the
// bounding box's centre rounded to the metre.
struct LasQuantisation {
    Eigen::Vector3d scale, offset;
};
LasQuantisation las_quantisation(const std::vector<Eigen::Vector3d>& xyz);

}  // namespace tlsmon
