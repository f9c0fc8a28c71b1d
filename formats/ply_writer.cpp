#include "formats/ply_writer.hpp"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/error.hpp"

namespace tlsmon {

static_assert(std::endian::native == std::endian::little, "the PLY writer writes native bytes");

namespace {

const char* type_name(const PlyAttribute& a) {
    switch (a.values.index()) {
        case 0:
            return "float";
        case 1:
            return "int";
        default:
            return "uchar";
    }
}

std::size_t count(const PlyAttribute& a) {
    return std::visit([](const auto& v) { return v.size(); }, a.values);
}

}  // namespace

void write_ply(const std::filesystem::path& path, std::span<const Eigen::Vector3d> points,
               std::span<const PlyAttribute> attributes) {
    for (const auto& a : attributes)
        if (count(a) != points.size())
            throw Error(path.string() + ": attribute " + a.name + " has " +
                        std::to_string(count(a)) + " values for " + std::to_string(points.size()) +
                        " points");
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(path.string() + ": cannot write: " + std::strerror(errno));
    out << "ply\nformat binary_little_endian 1.0\ncomment written by tlsmon\nelement vertex "
        << points.size() << "\nproperty double x\nproperty double y\nproperty double z\n";
    for (const auto& a : attributes) out << "property " << type_name(a) << " " << a.name << "\n";
    out << "end_header\n";
    std::vector<char> record;
    for (std::size_t i = 0; i < points.size(); ++i) {
        record.clear();
        const auto put = [&](const auto& value) {
            const char* bytes = reinterpret_cast<const char*>(&value);
            record.insert(record.end(), bytes, bytes + sizeof(value));
        };
        put(points[i].x());
        put(points[i].y());
        put(points[i].z());
        for (const auto& a : attributes) std::visit([&](const auto& v) { put(v[i]); }, a.values);
        out.write(record.data(), std::streamsize(record.size()));
    }
    out.close();
    if (!out) throw Error(path.string() + ": write failed: " + std::strerror(errno));
}

}  // namespace tlsmon
