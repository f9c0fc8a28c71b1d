#include "formats/scan_file.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <fstream>

#include "core/error.hpp"
#include "formats/ascii_reader.hpp"
#include "formats/e57_reader.hpp"
#include "formats/format_error.hpp"
#include "formats/las_reader.hpp"
#include "formats/mapped_file.hpp"
#include "formats/pcd_reader.hpp"
#include "formats/ply_reader.hpp"
#include "formats/ptx_reader.hpp"

namespace tlsmon {

namespace {

using ParseFunction = std::vector<Scan> (*)(std::string_view bytes,
                                            const std::filesystem::path& path);

struct FormatEntry {
    ScanFormat format;
    std::string_view name;
    std::array<std::string_view, 3> extensions;  // the first is the one ingest takes
    std::array<std::string_view, 2> magic;       // none for PTX, PTS and XYZ
    ParseFunction parse;
};

std::vector<Scan> parse_las_file(std::string_view bytes, const std::filesystem::path& path) {
    return {parse_las(bytes.data(), bytes.size(), path)};
}

std::vector<Scan> parse_e57_file(std::string_view bytes, const std::filesystem::path& path) {
    return parse_e57(bytes.data(), bytes.size(), path);
}

// Each reader adds its row here. LAZ shares the LAS reader, which reads a .laz that is in
// fact uncompressed and rejects compressed data with a clear message; LAZ has no magic of
// its own ("LASF" is LAS's).
constexpr std::array<FormatEntry, 8> formats = {{
    {ScanFormat::ptx, "PTX", {"ptx"}, {}, parse_ptx},
    {ScanFormat::pts, "PTS", {"pts"}, {}, parse_pts},
    {ScanFormat::xyz, "XYZ", {"xyz", "txt", "asc"}, {}, parse_xyz},
    {ScanFormat::ply, "PLY", {"ply"}, {"ply"}, parse_ply},
    {ScanFormat::pcd, "PCD", {"pcd"}, {"# .PCD", "VERSION"}, parse_pcd},
    {ScanFormat::las, "LAS", {"las"}, {"LASF"}, parse_las_file},
    {ScanFormat::laz, "LAZ", {"laz"}, {}, parse_las_file},
    {ScanFormat::e57, "E57", {"e57"}, {"ASTM-E57"}, parse_e57_file},
}};

const FormatEntry* entry(ScanFormat f) {
    for (const auto& e : formats) {
        if (e.format == f) return &e;
    }
    return nullptr;
}

ScanFormat by_magic(std::string_view head) {
    for (const auto& e : formats) {
        for (std::string_view m : e.magic) {
            if (!m.empty() && head.starts_with(m)) return e.format;
        }
    }
    return ScanFormat::unknown;
}

ScanFormat by_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    if (ext.empty()) return ScanFormat::unknown;
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::string_view name = std::string_view(ext).substr(1);
    for (const auto& e : formats) {
        for (std::string_view x : e.extensions) {
            if (!x.empty() && x == name) return e.format;
        }
    }
    return ScanFormat::unknown;
}

}  // namespace

std::string to_string(ScanFormat f) {
    const FormatEntry* e = entry(f);
    return e ? std::string(e->name) : "unknown";
}

std::vector<std::string> scan_extensions() {
    std::vector<std::string> out;
    for (const auto& e : formats) out.emplace_back(e.extensions[0]);
    return out;
}

ScanFormat detect_format(const std::filesystem::path& path) {
    const ScanFormat f = by_extension(path);
    if (f != ScanFormat::unknown) return f;
    std::ifstream in(path, std::ios::binary);
    char head[8] = {};
    in.read(head, sizeof head);
    return by_magic(std::string_view(head, static_cast<std::size_t>(in.gcount())));
}

std::vector<Scan> read_scans(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_scans(file.text(), path);
}

std::vector<Eigen::Vector3d> all_points(const std::vector<Scan>& scans, const std::string& source) {
    std::size_t n = 0;
    for (const Scan& scan : scans) n += scan.xyz.size();
    if (n == 0) throw Error(source + ": no points");
    std::vector<Eigen::Vector3d> out;
    out.reserve(n);
    for (const Scan& scan : scans) out.insert(out.end(), scan.xyz.begin(), scan.xyz.end());
    return out;
}

void check_coordinates(const std::vector<Scan>& scans, const std::filesystem::path& path) {
    for (std::size_t k = 0; k < scans.size(); ++k) {
        const Scan& s = scans[k];
        const auto at = [&](std::size_t i) {
            return "scan " + std::to_string(k + 1) + ", point " + std::to_string(i + 1);
        };
        for (std::size_t i = 0; i < s.xyz.size(); ++i) {
            const Eigen::Vector3d& p = s.xyz[i];
            if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate) {
                char where[96];
                std::snprintf(where, sizeof where, "(%g, %g, %g)", p.x(), p.y(), p.z());
                throw_format_error(path, at(i) + " lies at " + where +
                                             ", beyond 1e8 m: the file's coordinates, scale, "
                                             "offset or transformation are corrupt");
            }
        }
        const Eigen::Vector3d o = s.scanner_position();
        if (!o.allFinite() || o.cwiseAbs().maxCoeff() > kMaxCoordinate) {
            throw_format_error(path, "scan " + std::to_string(k + 1) +
                                         ": the scanner's position is not finite or beyond "
                                         "1e8 m: its pose is corrupt");
        }
    }
}

std::vector<Scan> parse_scans(std::string_view bytes, const std::filesystem::path& path) {
    ScanFormat format = by_extension(path);
    if (format == ScanFormat::unknown) format = by_magic(bytes.substr(0, 8));
    const FormatEntry* e = entry(format);
    if (!e) throw_format_error(path, "no reader for format " + to_string(format));
    std::vector<Scan> scans = e->parse(bytes, path);
    check_coordinates(scans, path);
    return scans;
}

}  // namespace tlsmon
