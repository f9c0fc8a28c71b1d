// PLY reading speed on one core: a generated 5-million-point cloud written as binary and
// as ASCII PLY (float x y z, uchar red green blue, float scalar_Intensity, as CloudCompare
// exports a scan). Prints MB/s and points/s, median and spread of several runs, with the
// file in the page cache.
//
// Usage: bench_read_ply [FOLDER]   without FOLDER the files go into a private temporary
// folder removed at the end; with FOLDER they are written there and kept (to time another
// program on the very same files).
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "formats/ply_reader.hpp"

namespace fs = std::filesystem;

namespace {

constexpr int columns = 2500, rows = 2000;  // 5,000,000 points

struct Point {
    float x, y, z;
    std::uint8_t r, g, b;
    float intensity;
};

Point point(int c, int r) {
    const double azimuth = 2.0 * std::numbers::pi * c / columns;
    const double elevation = -1.2 + 2.4 * r / rows;
    const double range = 5.0 + 20.0 * std::abs(std::sin(0.37 * c + 0.11 * r));
    return {static_cast<float>(range * std::cos(elevation) * std::cos(azimuth)),
            static_cast<float>(range * std::cos(elevation) * std::sin(azimuth)),
            static_cast<float>(range * std::sin(elevation)),
            static_cast<std::uint8_t>(c % 256),
            static_cast<std::uint8_t>(r % 256),
            128,
            static_cast<float>(0.2 + 0.6 * ((c * rows + r) % 1000) / 1000.0)};
}

std::string header(const char* format) {
    return std::string("ply\nformat ") + format + " 1.0\nelement vertex " +
           std::to_string(columns * rows) +
           "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
           "property uchar green\nproperty uchar blue\nproperty float scalar_Intensity\n"
           "end_header\n";
}

void append(std::string& out, float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 6);
    out.append(buf, r.ptr);
}

void write_files(const fs::path& binary, const fs::path& ascii) {
    std::ofstream bin(binary, std::ios::binary), txt(ascii, std::ios::binary);
    bin << header("binary_little_endian");
    txt << header("ascii");
    std::string b, t;
    for (int c = 0; c < columns; ++c) {
        for (int r = 0; r < rows; ++r) {
            const Point p = point(c, r);
            char rec[19];
            std::memcpy(rec, &p.x, 4), std::memcpy(rec + 4, &p.y, 4), std::memcpy(rec + 8, &p.z, 4);
            rec[12] = static_cast<char>(p.r), rec[13] = static_cast<char>(p.g);
            rec[14] = static_cast<char>(p.b);
            std::memcpy(rec + 15, &p.intensity, 4);
            b.append(rec, sizeof rec);
            append(t, p.x), t += ' ', append(t, p.y), t += ' ', append(t, p.z);
            t += ' ' + std::to_string(p.r) + ' ' + std::to_string(p.g) + ' ' + std::to_string(p.b) +
                 ' ';
            append(t, p.intensity);
            t += '\n';
        }
        if (t.size() > (1u << 22)) {
            bin << b, txt << t;
            b.clear(), t.clear();
        }
    }
    bin << b, txt << t;
}

}  // namespace

int main(int argc, char** argv) {
    std::unique_ptr<tlsmon::bench::BenchDir> temporary;
    fs::path folder;
    if (argc > 1) {
        folder = argv[1];
        fs::create_directories(folder);
    } else {
        temporary = std::make_unique<tlsmon::bench::BenchDir>();
        folder = *temporary / "";
    }
    const fs::path binary = folder / "generated_5M_binary.ply";
    const fs::path ascii = folder / "generated_5M_ascii.ply";
    std::printf("writing %s and %s ...\n", binary.c_str(), ascii.c_str());
    write_files(binary, ascii);
    tlsmon::bench::measure_reader(binary, 7, [](const fs::path& p) { return tlsmon::read_ply(p); });
    tlsmon::bench::measure_reader(ascii, 5, [](const fs::path& p) { return tlsmon::read_ply(p); });
}
