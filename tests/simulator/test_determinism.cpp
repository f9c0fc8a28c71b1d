// Seeded and deterministic: the same seed gives the same bytes (on 1 or 2 threads), a
// different seed different bytes, and a window cut out of a scan the scan's own noise.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <map>
#include <utility>

#include "core/error.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "simulator/series.hpp"
#include "tests/simulator/narrow_window.hpp"

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

// A window's cells carry the whole scan's points at the same cells, noise included: two
// windows of one shape about two targets do not share one noise field (docs/simulator.md).
TEST(SimulatorDeterminism, AWindowCutOutOfAScanCarriesTheScansNoiseAtEachCell) {
    const Site site = preset_small();
    const EpochConditions c = epoch_conditions(site, 2, 5.0);
    const Scan whole = render_epoch(site, c, 2).scan;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> at;  // (row, column) -> point
    for (std::size_t i = 0; i < whole.size(); ++i)
        at[{whole.grid->row[i], whole.grid->column[i]}] = i;
    Site narrowed = site;
    test::narrow_window(narrowed.scanner, site.targets.at(1).centre, 1.0);
    ASSERT_GT(narrowed.scanner.first_column + narrowed.scanner.first_row, 0u);
    const Scan window = render_epoch(narrowed, c, 2).scan;
    ASSERT_GT(window.size(), 100u);
    double worst = 0, worst_intensity = 0;
    for (std::size_t i = 0; i < window.size(); ++i) {
        const auto found = at.find({window.grid->row[i] + narrowed.scanner.first_row,
                                    window.grid->column[i] + narrowed.scanner.first_column});
        ASSERT_NE(found, at.end()) << "a window's cell the whole scan has no return at";
        worst = std::max(worst, (whole.xyz[found->second] - window.xyz[i]).norm());
        worst_intensity =
            std::max(worst_intensity,
                     double(std::abs(whole.intensity[found->second] - window.intensity[i])));
    }
    // The same draws (the noise: 0.2–0.8 mm in range, 3″ in angle, 0.01 in intensity), up
    // to the rounding of the shifted window's angles.
    EXPECT_LT(worst, 1e-9);
    EXPECT_LT(worst_intensity, 1e-6);
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
