#include "formats/scan_file.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>

#include "formats/ascii_reader.hpp"
#include "formats/e57_reader.hpp"
#include "formats/format_error.hpp"
#include "formats/las_reader.hpp"
#include "formats/pcl_formats.hpp"
#include "formats/ptx_reader.hpp"

namespace tlsmon {

std::string to_string(ScanFormat f) {
    switch (f) {
        case ScanFormat::ptx:
            return "PTX";
        case ScanFormat::pts:
            return "PTS";
        case ScanFormat::xyz:
            return "XYZ";
        case ScanFormat::ply:
            return "PLY";
        case ScanFormat::pcd:
            return "PCD";
        case ScanFormat::las:
            return "LAS";
        case ScanFormat::laz:
            return "LAZ";
        case ScanFormat::e57:
            return "E57";
        case ScanFormat::unknown:
            break;
    }
    return "unknown";
}

namespace {

ScanFormat by_magic(std::string_view head) {
    const auto starts = [&](const char* magic) { return head.starts_with(magic); };
    if (starts("ASTM-E57")) return ScanFormat::e57;
    if (starts("LASF")) return ScanFormat::las;
    if (starts("ply")) return ScanFormat::ply;
    if (starts("# .PCD") || starts("VERSION")) return ScanFormat::pcd;
    return ScanFormat::unknown;
}

ScanFormat by_magic(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char head[8] = {};
    in.read(head, sizeof head);
    return by_magic(std::string_view(head, static_cast<std::size_t>(in.gcount())));
}

ScanFormat by_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".ptx") return ScanFormat::ptx;
    if (ext == ".pts") return ScanFormat::pts;
    if (ext == ".xyz" || ext == ".txt" || ext == ".asc") return ScanFormat::xyz;
    if (ext == ".ply") return ScanFormat::ply;
    if (ext == ".pcd") return ScanFormat::pcd;
    if (ext == ".las") return ScanFormat::las;
    if (ext == ".laz") return ScanFormat::laz;
    if (ext == ".e57") return ScanFormat::e57;
    return ScanFormat::unknown;
}

}  // namespace

ScanFormat detect_format(const std::filesystem::path& path) {
    const ScanFormat f = by_extension(path);
    return f != ScanFormat::unknown ? f : by_magic(path);
}

std::vector<Scan> read_scans(const std::filesystem::path& path) {
    const ScanFormat format = detect_format(path);
    switch (format) {
        // Each reader adds its case here.
        case ScanFormat::las:  // a .laz that is in fact uncompressed is read too
        case ScanFormat::laz:
            return read_las(path);
        case ScanFormat::ply:
            return read_ply(path);
        case ScanFormat::pcd:
            return read_pcd(path);
        case ScanFormat::ptx:
            return read_ptx(path);
        case ScanFormat::pts:
            return read_pts(path);
        case ScanFormat::xyz:
            return read_xyz(path);
        case ScanFormat::e57:
            return read_e57(path);
        default:
            break;
    }
    throw_format_error(path, "no reader for format " + to_string(format));
}

std::vector<Scan> parse_scans(std::string_view bytes, const std::filesystem::path& path) {
    ScanFormat format = by_extension(path);
    if (format == ScanFormat::unknown) format = by_magic(bytes.substr(0, 8));
    switch (format) {
        case ScanFormat::las:
        case ScanFormat::laz:
            return {parse_las(bytes.data(), bytes.size(), path)};
        case ScanFormat::ptx:
            return parse_ptx(bytes, path);
        case ScanFormat::pts:
            return parse_pts(bytes, path);
        case ScanFormat::xyz:
            return parse_xyz(bytes, path);
        case ScanFormat::e57:
            return parse_e57(bytes.data(), bytes.size(), path);
        case ScanFormat::ply:  // PCL reads the file itself
        case ScanFormat::pcd:
            return read_scans(path);
        default:
            break;
    }
    throw_format_error(path, "no reader for format " + to_string(format));
}

}  // namespace tlsmon
