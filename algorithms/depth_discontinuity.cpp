#include "algorithms/depth_discontinuity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon {

namespace {

// A step changes the range's slope by more than half the larger of its two sides; a plane seen
// at grazing incidence on a coarse grid changes it by a few per cent (its second difference
// over its first is about 2·Δθ·tan α: 0.07 at 87° and 0.1°, where the second difference itself
// reaches 0.1 m).
constexpr double kStepShare = 0.5;

}  // namespace

std::vector<std::uint8_t> depth_discontinuities(const Scan& scan, double jump, unsigned threads,
                                                bool with_neighbours) {
    if (!(jump > 0)) throw Error("depth discontinuities: the jump must be > 0");
    if (!scan.grid) return {};
    const ScanGrid& g = *scan.grid;
    if (g.row.size() != scan.size() || g.column.size() != scan.size())
        throw Error("depth discontinuities: the grid does not match the points");
    if (g.too_sparse())
        throw Error("depth discontinuities: the grid has far more cells than points");
    // A cell without a return inside the grid: nothing there, or too weak a return (a
    // grazing face); outside the grid: not known.
    constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
    constexpr std::uint32_t kOutside = kEmpty - 1;
    std::vector<std::uint32_t> at(g.cells(), kEmpty);
    for (std::size_t i = 0; i < scan.size(); ++i)
        at[std::size_t(g.row[i]) * g.columns + g.column[i]] = std::uint32_t(i);
    const Eigen::Vector3d origin = scan.scanner_position();
    const auto point = [&](long r, long c) {
        if (r < 0 || c < 0 || r >= long(g.rows) || c >= long(g.columns)) return kOutside;
        return at[std::size_t(r) * g.columns + std::size_t(c)];
    };
    // The passes in blocks of points, each point writing its own entry only.
    constexpr std::size_t kBlock = 1 << 16;
    const std::size_t blocks = (scan.size() + kBlock - 1) / kBlock;
    const auto each_point = [&](auto&& visit) {
        parallel_for(
            blocks,
            [&](std::size_t b) {
                for (std::size_t i = b * kBlock; i < std::min(scan.size(), (b + 1) * kBlock); ++i)
                    visit(i, long(g.row[i]), long(g.column[i]));
            },
            threads);
    };
    // Each range once: the second differences read every point's up to five times.
    std::vector<double> range(scan.size());
    each_point([&](std::size_t i, long, long) { range[i] = (scan.xyz[i] - origin).norm(); });
    std::vector<std::uint8_t> step(scan.size(), 0);
    each_point([&](std::size_t i, long r, long c) {
        const double here = range[i];
        for (const auto& [a, b] : {std::pair{point(r - 1, c), point(r + 1, c)},
                                   std::pair{point(r, c - 1), point(r, c + 1)}}) {
            if (a == kOutside || b == kOutside) continue;
            if (a == kEmpty || b == kEmpty) {
                step[i] = 1;
                continue;
            }
            const double before = here - range[a], after = range[b] - here;
            const double second = std::abs(after - before);
            if (second > jump && second > kStepShare * std::max(std::abs(before), std::abs(after)))
                step[i] = 1;
        }
    });
    std::vector<std::uint8_t> marked(scan.size(), 0);
    each_point([&](std::size_t i, long r, long c) {
        marked[i] = step[i];
        if (!with_neighbours) return;
        for (const auto j : {point(r - 1, c), point(r + 1, c), point(r, c - 1), point(r, c + 1)})
            if (j < kOutside && step[j]) marked[i] = 1;
    });
    return marked;
}

}  // namespace tlsmon
