// The registration stage on one full scan: `bench_registration EPOCH.ptx SITE.toml
// [--parse-only]`, e.g. an epoch and the site.toml of `tlsmon simulate --preset pier`
// (≈ 6.8 M points). The scan is parsed once; the reference centres are measured on it (in
// the daemon they come from the reference cache); then the registration (every target
// found through the grid's angular window, fitted, the tested adjustment) is timed over
// several runs. `--parse-only` stops after parsing, so a whole-process timing of both gives
// the registration's share by difference.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "bench/bench_support.hpp"
#include "config/config.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/sha256.hpp"

int main(int argc, char** argv) {
    using namespace tlsmon;
    if (argc < 3) {
        std::fprintf(stderr, "usage: bench_registration EPOCH.ptx SITE.toml [--parse-only]\n");
        return 2;
    }
    const bool parse_only = argc > 3 && std::strcmp(argv[3], "--parse-only") == 0;
    const auto t0 = std::chrono::steady_clock::now();
    const HashedBytes content = read_file_hashed(argv[1]);
    const std::vector<Scan> scans = parse_scans(content.bytes, argv[1]);
    const double parse_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::size_t points = 0;
    for (const auto& s : scans) points += s.size();
    std::printf("parsed %zu points in %.2f s\n", points, parse_s);
    if (parse_only) return 0;
    const RegistrationConfig config = pipeline_config(load_config(argv[2])).registration;
    const ReferenceTargets reference = measure_reference_targets(config, scans);
    std::vector<double> times;
    RegistrationResult r;
    for (int run = 0; run < 5; ++run) {
        const auto t = std::chrono::steady_clock::now();
        r = register_epoch(config, reference, scans, {});
        times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
    }
    const auto s = bench::spread_of(times);
    std::printf(
        "registration of %zu targets (%d used, %s): median %.4f s (min %.4f, max %.4f) "
        "over %zu runs\n",
        config.targets.size(), r.used, r.accepted() ? "accepted" : "refused", s.median, s.min,
        s.max, s.runs);
    return 0;
}
