// The archive policy over a year of a simulated scene (docs/retention.md;
// `bench_archive_year [PRESET]`, the demo's `small` by default): one scan of the scene is
// simulated and written as the scanner's PTX, re-encoded as E57 by the archive's own
// re-encoding (timed, CPU and wall), and a year of 96 scans a day of those sizes is run
// through the policy's plan once a simulated day (the default policy: every scan for 7 days,
// the day's first until 90, then the week's first). Prints the archive's size after 1, 6 and
// 12 months with every scan kept, with the policy, and with the policy and the E57
// re-encoding. The sizes of one PTX and one E57 are measured; the year is the plan applied
// to them (writing 35,040 scan files is not what a bench can do).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

#include "bench/bench_support.hpp"
#include "daemon/scan_reencoding.hpp"
#include "pipeline/sha256.hpp"
#include "simulator/series.hpp"
#include "storage/archive_policy.hpp"

namespace fs = std::filesystem;
using namespace tlsmon;

int main(int argc, char** argv) {
    const std::string preset = argc > 1 ? argv[1] : "small";
    bench::BenchDir dir;
    const std::int64_t start = sim::parse_utc("2026-06-01T06:00:00Z");
    const auto files = sim::simulate_epoch(sim::preset(preset), 0, start);
    const fs::path ptx = dir / (files.stem + ".ptx");
    std::ofstream(ptx, std::ios::binary) << files.ptx;
    const auto ptx_bytes = static_cast<std::int64_t>(fs::file_size(ptx));

    ArchivePolicy policy;
    policy.enabled = true;
    policy.reencode = ScanReencoding::e57;
    const double c0 = bench::process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    const auto e57 = reencode_as_e57(ptx, sha256_file(ptx), policy.e57_resolution);
    const double wall = bench::seconds_since(t0), cpu = bench::process_cpu_seconds() - c0;
    std::printf(
        "one scan of the small scene: PTX %.1f MB, E57 %.1f MB (%.0f %%); re-encoded, "
        "read back and compared in %.2f s wall, %.2f s CPU\n",
        ptx_bytes / 1e6, e57.bytes / 1e6, 100.0 * e57.bytes / ptx_bytes, wall, cpu);

    constexpr int per_day = 96;
    std::vector<ArchivedScan> kept, kept_e57;  // the archive with the policy, without/with E57
    std::int64_t id = 0;
    std::printf("%-9s %8s %18s %18s %22s\n", "after", "scans", "every scan kept", "with the policy",
                "policy + E57");
    for (int day = 1; day <= 365; ++day) {
        for (int k = 0; k < per_day; ++k) {
            ++id;
            const UtcSeconds t = start + (day - 1) * 86400 + k * 900;
            const ArchivedScan s{id, t, "s.ptx", "", ptx_bytes, id == 1, id == 1, false};
            kept.push_back(s);
            kept_e57.push_back(s);
        }
        const UtcSeconds now = kept.back().acquired;
        ArchivePolicy plain = policy;
        plain.reencode = ScanReencoding::none;
        const auto thin = [&](std::vector<ArchivedScan>& archive, const ArchivePolicy& p) {
            const auto plan = plan_archive(archive, now, p);
            std::set<EpochId> gone;
            for (const auto& s : plan.remove) gone.insert(s.id);
            std::set<EpochId> reencode;
            for (const auto& s : plan.reencode) reencode.insert(s.id);
            std::erase_if(archive, [&](const ArchivedScan& s) { return gone.count(s.id) > 0; });
            for (auto& s : archive) {
                if (reencode.count(s.id)) s.path = "s.e57", s.bytes = e57.bytes;
            }
        };
        thin(kept, plain);
        thin(kept_e57, policy);
        if (day == 30 || day == 182 || day == 365) {
            const auto total = [](const std::vector<ArchivedScan>& a) {
                std::int64_t b = 0;
                for (const auto& s : a) b += s.bytes;
                return b;
            };
            std::printf("%-9s %8lld %15.1f GB %15.1f GB %19.1f GB   (%zu scans kept)\n",
                        day == 30    ? "1 month"
                        : day == 182 ? "6 months"
                                     : "12 months",
                        static_cast<long long>(id), id * ptx_bytes / 1e9, total(kept) / 1e9,
                        total(kept_e57) / 1e9, kept.size());
        }
    }
    return 0;
}
