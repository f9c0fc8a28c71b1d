#pragma once
// Points with per-point attributes as a binary little-endian PLY file (the format CloudCompare,
// MeshLab and PDAL read with every attribute as a scalar field): x, y, z as doubles, then each
// attribute as the type of its values (float, int, uchar).
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace tlsmon {

struct PlyAttribute {
    std::string name;
    std::variant<std::span<const float>, std::span<const std::int32_t>,
                 std::span<const std::uint8_t>>
        values;  // one per point
};

// Throws Error naming the file when it cannot be written, or when an attribute's count
// differs from the points'.
void write_ply(const std::filesystem::path& path, std::span<const Eigen::Vector3d> points,
               std::span<const PlyAttribute> attributes);

}  // namespace tlsmon
