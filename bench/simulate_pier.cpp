// Rendering speed of the `pier` preset (≈ 10.5 M cells, ≈ 6.8 M points): points/s for the
// render on 1 and 2 threads, and for formatting the PTX text. Prints its numbers; nothing
// is asserted. Usage: bench_simulate_pier [threads...]   (default: 2 1)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "formats/ptx_writer.hpp"
#include "simulator/render.hpp"

int main(int argc, char** argv) {
    using clock = std::chrono::steady_clock;
    std::vector<unsigned> thread_counts;
    for (int i = 1; i < argc; ++i) thread_counts.push_back(std::atoi(argv[i]));
    if (thread_counts.empty()) thread_counts = {2, 1};

    const tlsmon::sim::Site site = tlsmon::sim::preset_pier();
    const auto shape = tlsmon::sim::grid_shape(site.scanner);
    std::printf("pier preset: %u rows x %u columns = %.2f M cells\n", shape.rows, shape.columns,
                shape.rows * static_cast<double>(shape.columns) / 1e6);
    tlsmon::sim::RenderedScan last;
    for (const unsigned threads : thread_counts) {
        const auto t0 = clock::now();
        const std::clock_t c0 = std::clock();
        last = tlsmon::sim::render_epoch(site, 12, 3.0, threads);
        const double s = std::chrono::duration<double>(clock::now() - t0).count();
        const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
        // CPU time too: on a shared machine the wall clock depends on the other load.
        std::printf(
            "render, %u thread(s): %zu points in %.2f s wall = %.2f M points/s (%.2f M "
            "cells/s); %.2f s CPU = %.2f M points per CPU-second\n",
            threads, last.scan.size(), s, last.scan.size() / s / 1e6,
            shape.rows * static_cast<double>(shape.columns) / s / 1e6, cpu,
            last.scan.size() / cpu / 1e6);
    }
    const auto t0 = clock::now();
    const std::string text = tlsmon::ptx_text(last.scan);
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    std::printf("PTX text (1 thread): %.1f MB in %.2f s = %.2f M points/s, %.0f MB/s\n",
                text.size() / 1e6, s, last.scan.size() / s / 1e6, text.size() / s / 1e6);
    return 0;
}
