// E57 reading speed: MB/s of file and points/s, on the real pump scan and on a large
// generated structured scan (ScaledInteger coordinates, 12-bit intensity, colour, grid).
// Usage: bench_read_e57 [points of the generated file, default 5000000]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_support.hpp"
#include "formats/e57_reader.hpp"
#include "formats/e57_writer.hpp"

namespace {

using Clock = std::chrono::steady_clock;

void measure(const char* what, const std::filesystem::path& file, int repeats) {
    const double mb = static_cast<double>(std::filesystem::file_size(file)) / 1e6;
    std::vector<double> seconds;
    std::size_t points = 0;
    for (int k = 0; k < repeats; ++k) {
        const auto t0 = Clock::now();
        const std::vector<tlsmon::Scan> scans = tlsmon::read_e57(file);
        seconds.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
        points = 0;
        for (const auto& s : scans) points += s.size();
    }
    std::printf("%s: %.1f MB, %zu points\n", what, mb, points);
    tlsmon::bench::print_rate("wall", tlsmon::bench::spread_of(seconds), mb,
                              static_cast<double>(points));
}

// A structured scan of about `n` points: columns of 1000 rows, every 5th cell empty.
tlsmon::Scan generated_scan(std::size_t n) {
    tlsmon::Scan s;
    s.name = "generated";
    const std::uint32_t rows = 1000;
    const auto columns = static_cast<std::uint32_t>((n * 5 / 4 + rows - 1) / rows);
    s.grid = tlsmon::ScanGrid{rows, columns, {}, {}};
    for (std::uint32_t c = 0; c < columns && s.size() < n; ++c)
        for (std::uint32_t r = 0; r < rows && s.size() < n; ++r) {
            if ((r + c) % 5 == 0) continue;
            const double az = 2 * M_PI * c / columns, el = -1.0 + 2.0 * r / rows;
            const double range = 5.0 + 20.0 * ((r * 31 + c * 17) % 1000) / 1000.0;
            s.xyz.emplace_back(range * std::cos(el) * std::cos(az),
                               range * std::cos(el) * std::sin(az), range * std::sin(el));
            s.intensity.push_back(static_cast<float>((r * 7 + c) % 4096) / 4095.0f);
            s.rgb.push_back({static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(c), 128});
            s.grid->row.push_back(r);
            s.grid->column.push_back(c);
        }
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 5000000;
    measure(
        "pump scan (real, 2.6 MB)",
        std::filesystem::path(TLSMON_DATA_DIR) / "e57" / "pumpARowColumnIndexNoInvalidPoints.e57",
        20);

    const tlsmon::bench::BenchDir dir;
    const auto file = dir / "generated.e57";
    {
        const auto t0 = Clock::now();
        tlsmon::write_e57(file, {generated_scan(n)}, {.coordinate_scale = 1e-4});
        std::printf("generated %zu points in %.1f s\n", n,
                    std::chrono::duration<double>(Clock::now() - t0).count());
    }
    measure("generated (ScaledInteger)", file, 5);

    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    std::printf("peak RSS %.0f MB (the generated Scan alone holds ~%.0f MB of output)\n",
                static_cast<double>(u.ru_maxrss) / 1024.0, static_cast<double>(n) * 39 / 1e6);
    return 0;
}
