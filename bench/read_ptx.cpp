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

// Wall time and this thread's CPU time (on a shared machine the CPU time is the one-core
// figure; the wall time includes waiting for the core).
void measure(const fs::path& path, int runs) {
    const double mb = static_cast<double>(fs::file_size(path)) / 1e6;
    std::vector<double> wall, cpu;
    std::size_t points = 0;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = tlsmon::bench::thread_cpu_seconds();
        const auto scans = tlsmon::read_ptx(path);
        cpu.push_back(tlsmon::bench::thread_cpu_seconds() - c0);
        wall.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        points = 0;
        for (const auto& scan : scans) points += scan.size();
    }
    const double n = static_cast<double>(points);
    std::printf("%s: %.1f MB, %zu points\n", path.filename().c_str(), mb, points);
    tlsmon::bench::print_rate("cpu", tlsmon::bench::spread_of(cpu), mb, n);
    tlsmon::bench::print_rate("wall", tlsmon::bench::spread_of(wall), mb, n);
}

}  // namespace

int main() {
    const tlsmon::bench::BenchDir dir;
    const fs::path generated = dir / "generated_5M.ptx";
    std::printf("writing %s ...\n", generated.c_str());
    write_scan(generated);
    measure(generated, 5);
    measure(fs::path(TLSMON_DATA_DIR) / "ptx" / "pumpA_from_e57.ptx", 9);
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    std::printf("peak RSS %.0f MB\n", static_cast<double>(u.ru_maxrss) / 1024.0);
}
