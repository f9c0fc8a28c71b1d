// PTX reading speed on one core: a generated 5-million-point scan (written to /tmp once)
// and the real pump-room scan. Prints MB/s and points/s, best of several runs, with the
// file in the page cache.
#include <time.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

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

double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Wall time and this thread's CPU time (on a shared machine the CPU time is the one-core
// figure; the wall time includes waiting for the core).
void measure(const fs::path& path, int runs) {
    const double mb = static_cast<double>(fs::file_size(path)) / 1e6;
    double best_wall = 1e30, best_cpu = 1e30;
    std::size_t points = 0;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = thread_cpu_seconds();
        const auto scans = tlsmon::read_ptx(path);
        best_cpu = std::min(best_cpu, thread_cpu_seconds() - c0);
        best_wall =
            std::min(best_wall,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        points = 0;
        for (const auto& scan : scans) points += scan.size();
    }
    const double n = static_cast<double>(points);
    std::printf("%s: %.1f MB, %zu points, best of %d\n", path.filename().c_str(), mb, points, runs);
    std::printf("  cpu  %.3f s: %.0f MB/s, %.2f M points/s\n", best_cpu, mb / best_cpu,
                n / best_cpu / 1e6);
    std::printf("  wall %.3f s: %.0f MB/s, %.2f M points/s\n", best_wall, mb / best_wall,
                n / best_wall / 1e6);
}

}  // namespace

int main() {
    const fs::path generated = "/tmp/tlsmon_bench_5M.ptx";
    if (!fs::exists(generated)) {
        std::printf("writing %s ...\n", generated.c_str());
        const fs::path partial = generated.string() + ".part";
        write_scan(partial);
        fs::rename(partial, generated);
    }
    measure(generated, 3);
    measure(fs::path(TLSMON_DATA_DIR) / "ptx" / "pumpA_from_e57.ptx", 5);
}
