// PTX reading speed on one core: a generated 5-million-point scan (written into a private
// temporary folder, removed at the end) and the real pump-room scan. Prints MB/s and
// points/s, median and spread of several runs, with the file in the page cache.
#include <sys/resource.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "formats/ptx_reader.hpp"

namespace fs = std::filesystem;

namespace {

void append(std::string& out, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 6);
    out.append(buf, r.ptr);
}

// A 2600-column × 2000-row scan of a room-sized scene, `x y z i r g b` lines like a scanner
// export, every 26th cell empty: 5,000,000 points of 5,200,000 cells.
void write_scan(const fs::path& path) {
    constexpr int columns = 2600, rows = 2000;
    std::ofstream out(path, std::ios::binary);
    out << columns << "\n"
        << rows << "\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
        << "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
    std::string chunk;
    long cell = 0;
    for (int c = 0; c < columns; ++c) {
        const double azimuth = 2.0 * std::numbers::pi * c / columns;
        for (int r = 0; r < rows; ++r, ++cell) {
            if (cell % 26 == 25) {
                chunk += "0 0 0 0.500000 0 0 0\n";
                continue;
            }
            const double elevation = -1.2 + 2.4 * r / rows;
            const double range = 5.0 + 20.0 * std::abs(std::sin(0.37 * c + 0.11 * r));
            append(chunk, range * std::cos(elevation) * std::cos(azimuth));
            chunk += ' ';
            append(chunk, range * std::cos(elevation) * std::sin(azimuth));
            chunk += ' ';
            append(chunk, range * std::sin(elevation));
            chunk += ' ';
            append(chunk, 0.2 + 0.6 * (cell % 1000) / 1000.0);
            chunk += ' ' + std::to_string(cell % 256) + ' ' + std::to_string(r % 256) + ' ' +
                     std::to_string(c % 256) + '\n';
        }
        if (chunk.size() > (1u << 22)) {
            out << chunk;
            chunk.clear();
        }
    }
    out << chunk;
}

}  // namespace

int main() {
    const tlsmon::bench::BenchDir dir;
    const fs::path generated = dir / "generated_5M.ptx";
    std::printf("writing %s ...\n", generated.c_str());
    write_scan(generated);
    tlsmon::bench::measure_reader(generated, 5,
                                  [](const fs::path& p) { return tlsmon::read_ptx(p); });
    tlsmon::bench::measure_reader(fs::path(TLSMON_DATA_DIR) / "ptx" / "pumpA_from_e57.ptx", 9,
                                  [](const fs::path& p) { return tlsmon::read_ptx(p); });
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    std::printf("peak RSS %.0f MB\n", static_cast<double>(u.ru_maxrss) / 1024.0);
}
