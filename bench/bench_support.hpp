#pragma once
// Shared by the bench programs: a private temporary folder (mkdtemp, removed at the end,
// so that runs by several users or in parallel never share a fixed /tmp path), and the
// median and spread of repeated timings.
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "tests/support/seconds_since.hpp"

namespace tlsmon::bench {

class BenchDir {
  public:
    BenchDir() {
        std::string pattern =
            (std::filesystem::temp_directory_path() / "tlsmon-bench-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
        path_ = pattern;
    }
    ~BenchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    BenchDir(const BenchDir&) = delete;
    BenchDir& operator=(const BenchDir&) = delete;

    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

  private:
    std::filesystem::path path_;
};

inline double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// CPU seconds of the whole process (every thread, a library's pool included): on a shared
// machine the wall time depends on the load, this does not.
inline double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// CPU seconds of the finished child processes (the commands a bench ran), user and system.
inline double children_cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_CHILDREN, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

using test::seconds_since;

// Median, fastest and slowest of repeated runs (seconds).
struct Spread {
    double median = 0, min = 0, max = 0;
    std::size_t runs = 0;
};

inline Spread spread_of(std::vector<double> seconds) {
    std::sort(seconds.begin(), seconds.end());
    Spread s;
    s.runs = seconds.size();
    if (seconds.empty()) return s;
    const std::size_t n = seconds.size();
    s.median = n % 2 ? seconds[n / 2] : (seconds[n / 2 - 1] + seconds[n / 2]) / 2;
    s.min = seconds.front();
    s.max = seconds.back();
    return s;
}

// "<label> median 0.412 s (0.398 .. 0.455, 5 runs): 250 MB/s, 12.1 M points/s"
inline void print_rate(const char* label, const Spread& s, double mb, double points) {
    std::printf(
        "  %-5s median %.3f s (%.3f .. %.3f, %zu runs): %.0f MB/s (%.0f .. %.0f), %.2f M "
        "points/s\n",
        label, s.median, s.min, s.max, s.runs, mb / s.median, mb / s.max, mb / s.min,
        points / s.median / 1e6);
}

// Reads `path` with `read` (path -> scans) `runs` times and prints its size, point count and
// the CPU (this thread) and wall rates: on a shared machine the CPU time is the one-core
// figure; the wall time includes waiting for the core.
template <class Read>
void measure_reader(const std::filesystem::path& path, int runs, Read&& read) {
    const double mb = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
    std::vector<double> wall, cpu;
    std::size_t points = 0;
    for (int k = 0; k < runs; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = thread_cpu_seconds();
        const auto scans = read(path);
        cpu.push_back(thread_cpu_seconds() - c0);
        wall.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        points = 0;
        for (const auto& scan : scans) points += scan.size();
    }
    const double n = static_cast<double>(points);
    std::printf("%s: %.1f MB, %zu points\n", path.filename().c_str(), mb, points);
    print_rate("cpu", spread_of(cpu), mb, n);
    print_rate("wall", spread_of(wall), mb, n);
}

}  // namespace tlsmon::bench
