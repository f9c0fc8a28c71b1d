// Rendering speed of the `pier` preset (≈ 10.5 M cells, ≈ 6.8 M points): points/s for the
// render on 1 and 2 threads, and for formatting the PTX text. Each measurement is repeated
// and printed as the median with the spread (min–max), since one run on a shared machine
// says little. Writes no files; nothing is asserted.
// Usage: bench_simulate_pier [--runs N] [threads...]   (defaults: 3 runs; threads 2 1)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <vector>

#include "formats/ptx_writer.hpp"
#include "simulator/render.hpp"

namespace {

using steady = std::chrono::steady_clock;

struct Spread {
    double median, min, max;
};

Spread spread(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    const double median = n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
    return {median, v.front(), v.back()};
}

double seconds_since(steady::time_point t0) {
    return std::chrono::duration<double>(steady::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 3;
    std::vector<unsigned> thread_counts;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
            runs = std::max(1, std::atoi(argv[++i]));
        } else {
            thread_counts.push_back(std::atoi(argv[i]));
        }
    }
    if (thread_counts.empty()) thread_counts = {2, 1};

    const tlsmon::sim::Site site = tlsmon::sim::preset_pier();
    const auto shape = tlsmon::sim::grid_shape(site.scanner);
    const double cells = shape.rows * static_cast<double>(shape.columns);
    std::printf("pier preset: %u rows x %u columns = %.2f M cells; %d runs each\n", shape.rows,
                shape.columns, cells / 1e6, runs);
    tlsmon::sim::RenderedScan last;
    for (const unsigned threads : thread_counts) {
        std::vector<double> wall, cpu;
        for (int r = 0; r < runs; ++r) {
            const auto t0 = steady::now();
            const std::clock_t c0 = std::clock();
            last = tlsmon::sim::render_epoch(site, 12, 3.0, threads);
            wall.push_back(seconds_since(t0));
            cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        }
        // CPU time too: on a shared machine the wall clock depends on the other load.
        const Spread w = spread(wall), c = spread(cpu);
        const double points = static_cast<double>(last.scan.size());
        std::printf(
            "render, %u thread(s): %.0f points; wall median %.2f s (%.2f–%.2f) = %.2f M "
            "points/s (%.2f M cells/s); CPU median %.2f s (%.2f–%.2f) = %.2f M points per "
            "CPU-second\n",
            threads, points, w.median, w.min, w.max, points / w.median / 1e6,
            cells / w.median / 1e6, c.median, c.min, c.max, points / c.median / 1e6);
    }
    std::vector<double> text_s;
    std::size_t text_bytes = 0;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = steady::now();
        text_bytes = tlsmon::ptx_text(last.scan).size();
        text_s.push_back(seconds_since(t0));
    }
    const Spread t = spread(text_s);
    const double points = static_cast<double>(last.scan.size());
    std::printf(
        "PTX text (1 thread): %.1f MB; median %.2f s (%.2f–%.2f) = %.2f M points/s, %.0f MB/s\n",
        text_bytes / 1e6, t.median, t.min, t.max, points / t.median / 1e6,
        text_bytes / t.median / 1e6);
    return 0;
}
