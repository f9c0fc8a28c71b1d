// Seeded and deterministic: the same seed gives the same bytes (on 1 or 2 threads), a
// different seed different bytes.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>

#include "core/error.hpp"
#include "simulator/series.hpp"

namespace tlsmon::sim {
namespace {

constexpr std::int64_t kStart = 1780293600;  // 2026-06-01T06:00:00Z

TEST(SimulatorDeterminism, SameSeedSameBytesDifferentSeedDifferentBytes) {
    Site s = preset_small();
    const auto t0 = std::chrono::steady_clock::now();
    const EpochFiles a = simulate_epoch(s, 5, kStart, 2);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "small preset, one epoch rendered and formatted: " << seconds << " s, "
              << a.ptx.size() << " bytes\n";
    const EpochFiles b = simulate_epoch(s, 5, kStart, 1);
    EXPECT_EQ(a.ptx.size(), b.ptx.size());
    EXPECT_TRUE(a.ptx == b.ptx) << "a render on 1 and 2 threads differs";
    EXPECT_EQ(a.truth.dump(), b.truth.dump());

    s.noise.seed += 1;
    const EpochFiles c = simulate_epoch(s, 5, kStart, 2);
    EXPECT_FALSE(a.ptx == c.ptx);
    // Another epoch with the same seed also differs (noise is drawn per epoch).
    s.noise.seed -= 1;
    const EpochFiles d = simulate_epoch(s, 6, kStart, 2);
    EXPECT_FALSE(a.ptx == d.ptx);
}

TEST(SimulatorDeterminism, FileNamesCarryTheAcquisitionTime) {
    EXPECT_EQ(parse_utc("2026-06-01T06:00:00Z"), kStart);
    EXPECT_EQ(format_utc(kStart + 15 * 60), "2026-06-01T06:15:00Z");
    EXPECT_EQ(scan_file_stem("P3", kStart + 18 * 3600 + 45 * 60), "P3_20260602T004500Z");
    EXPECT_THROW(parse_utc("2026-06-01 06:00:00"), Error);
    EXPECT_THROW(parse_utc("2026-02-30T06:00:00Z"), Error);
    const Site s = preset_small();
    const EpochFiles f = simulate_epoch(s, 3, kStart, 2);
    EXPECT_EQ(f.stem, "small_20260601T064500Z");
    EXPECT_EQ(f.truth["time_utc"], "2026-06-01T06:45:00Z");
}

}  // namespace
}  // namespace tlsmon::sim
