// A year of the small demo scene's results in the epoch database, with and without the
// retention policy (reported, not asserted): one epoch every 15 minutes (35,040), each with
// zone values (six zones x seven quantities) and per-core-point maps — M3C2's four float32 maps
// (distance, LoD95, n1, n2) of 3,042 core points, the demo scene's count (`tlsmon export --map
// m3c2` of a demo epoch), and PB-M3C2's four of 400 patches — written through the same commit as
// the daemon. One database keeps every map; the other runs a pass of the default policy (30 days,
// then daily, then weekly) after each simulated day. Prints the database size (page_count x
// page_size, and the file with its WAL) after 1, 6 and 12 months, and the passes' times.
// Usage: bench_retention_year [DIR] [DAYS]  (DIR kept for inspection; default a temporary
// folder, removed; DAYS default 365).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "daemon/retention_pass.hpp"

namespace fs = std::filesystem;
using namespace tlsmon;
using Clock = std::chrono::steady_clock;

namespace {

constexpr UtcSeconds kStart = 1767225600;  // 2026-01-01T00:00:00Z
constexpr int kPerDay = 96;
constexpr int kCorePoints = 3042;
constexpr int kPatches = 400;
const char* const kZones[] = {"pier_south_top", "pier_south_face", "pier_west_face",
                              "deck_band_1",    "deck_band_2",     "abutment_check"};
const char* const kQuantities[] = {"m3c2_median_m",   "m3c2_mean_m",    "m3c2_lod95_m",
                                   "pbm3c2_median_m", "pbm3c2_lod95_m", "keypoint_dx_m",
                                   "keypoint_dz_m"};

std::vector<float> wave(int n, int epoch, double amplitude) {
    std::vector<float> v(n);
    for (int k = 0; k < n; ++k) v[k] = static_cast<float>(amplitude * std::sin(0.37 * k + epoch));
    return v;
}

EpochResults results(int i) {
    EpochResults r;
    for (const char* z : kZones)
        for (const char* q : kQuantities)
            r.zone_results.push_back({z, q, 1e-4 * std::sin(i * 0.01), 0.002, 300, false});
    r.core_point_arrays = {{"m3c2_distance_m", wave(kCorePoints, i, 0.002)},
                           {"m3c2_lod95_m", wave(kCorePoints, i + 1, 0.001)},
                           {"m3c2_n1", wave(kCorePoints, i + 2, 40)},
                           {"m3c2_n2", wave(kCorePoints, i + 3, 40)},
                           {"pbm3c2_distance_m", wave(kPatches, i, 0.002)},
                           {"pbm3c2_lod95_m", wave(kPatches, i + 1, 0.001)},
                           {"pbm3c2_n1", wave(kPatches, i + 2, 300)},
                           {"pbm3c2_n2", wave(kPatches, i + 3, 300)}};
    return r;
}

double mib(std::int64_t bytes) {
    return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

std::int64_t on_disk(const fs::path& db) {
    std::error_code ec;
    const auto wal = fs::file_size(db.string() + "-wal", ec);
    return static_cast<std::int64_t>(fs::file_size(db) + (ec ? 0 : wal));
}

}  // namespace

int main(int argc, char** argv) {
    const bool keep = argc > 1;
    const fs::path dir = keep ? fs::path(argv[1]) : fs::temp_directory_path() / "tlsmon-retention";
    const int days = argc > 2 ? std::stoi(argv[2]) : 365;
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto kept = EpochDatabase::open(dir / "every-map.sqlite", EpochDatabase::Mode::read_write);
    auto thinned = EpochDatabase::open(dir / "retention.sqlite", EpochDatabase::Mode::read_write);
    for (auto* db : {&kept, &thinned})
        for (const char* z : kZones) db->site().upsert_zone(z, "{}");
    const RetentionPolicy policy;
    std::vector<double> pass_ms;
    std::printf("%d days of %d epochs; maps per epoch: 4 x %d + 4 x %d float32 (%.1f kB)\n", days,
                kPerDay, kCorePoints, kPatches, 16.0 * (kCorePoints + kPatches) / 1000.0);
    std::printf("%6s %10s %22s %22s %10s\n", "month", "epochs", "every map (MiB)",
                "retention (MiB)", "with maps");
    for (int day = 0; day < days; ++day) {
        for (int e = 0; e < kPerDay; ++e) {
            const int i = day * kPerDay + e;
            char sha[65];
            std::snprintf(sha, sizeof sha, "%064x", i + 1);
            const EpochResults r = results(i);
            for (auto* db : {&kept, &thinned}) {
                const auto id = db->epochs()
                                    .insert({sha, kStart + 900LL * i, "/ingest/scan.ptx",
                                             180'000'000, std::nullopt})
                                    .id;
                db->epochs().claim(id);
                if (i == 0) db->epochs().set_reference(id);
                db->results().commit(id, r);
            }
        }
        const auto t = Clock::now();
        const auto pass = run_retention_pass(thinned, policy);
        pass_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
        const int month_end[] = {30, 182, 365};
        if (std::find(std::begin(month_end), std::end(month_end), day + 1) != std::end(month_end) ||
            day + 1 == days) {
            const auto with_maps = pass.plan.kept_young + pass.plan.kept_daily +
                                   pass.plan.kept_weekly + pass.plan.kept_protected;
            std::printf("%6.1f %10d %10.1f (%7.1f) %10.1f (%7.1f) %10lld\n", (day + 1) / 30.4,
                        (day + 1) * kPerDay, mib(kept.retention().size_bytes()),
                        mib(on_disk(kept.path())), mib(thinned.retention().size_bytes()),
                        mib(on_disk(thinned.path())), static_cast<long long>(with_maps));
            std::fflush(stdout);
        }
    }
    std::sort(pass_ms.begin(), pass_ms.end());
    std::printf("daily retention pass: median %.1f ms, max %.1f ms (n=%zu)\n",
                pass_ms[pass_ms.size() / 2], pass_ms.back(), pass_ms.size());
    if (!keep) fs::remove_all(dir);
    return 0;
}
