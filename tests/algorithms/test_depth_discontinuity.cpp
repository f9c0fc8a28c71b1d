// Depth discontinuities of a structured scan against grids whose ranges are known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "algorithms/depth_discontinuity.hpp"
#include "core/error.hpp"

namespace tlsmon {
namespace {

// A grid of `rows` × `columns` beams from the origin, `step_deg` apart in azimuth and
// elevation about the +y axis, each at the range `range(r, c)` (NaN: no return).
Scan grid_scan(std::uint32_t rows, std::uint32_t columns,
               const std::function<double(double azimuth, std::uint32_t r, std::uint32_t c)>& range,
               double step_deg = 0.013) {
    const double step = step_deg * M_PI / 180;
    Scan s;
    ScanGrid g;
    g.rows = rows, g.columns = columns;
    for (std::uint32_t r = 0; r < rows; ++r)
        for (std::uint32_t c = 0; c < columns; ++c) {
            const double azimuth = step * (double(c) - 0.5 * columns);
            const double elevation = step * (double(r) - 0.5 * rows);
            const double d = range(azimuth, r, c);
            if (std::isnan(d)) continue;
            s.xyz.push_back(d * Eigen::Vector3d(std::sin(azimuth) * std::cos(elevation),
                                                std::cos(azimuth) * std::cos(elevation),
                                                std::sin(elevation)));
            g.row.push_back(r), g.column.push_back(c);
        }
    s.grid = std::move(g);
    return s;
}

// Which columns of row `row` are marked (every cell of the row returned).
std::vector<int> marked_columns(const Scan& s, const std::vector<std::uint8_t>& m,
                                std::uint32_t row) {
    std::vector<int> out;
    for (std::size_t i = 0; i < s.size(); ++i)
        if (s.grid->row[i] == row && m[i]) out.push_back(int(s.grid->column[i]));
    return out;
}

TEST(DepthDiscontinuities, AStepBetweenTwoFacesMarksTheBeamsBesideIt) {
    // A face 50 m away, and from column 10 on a face 0.2 m behind it.
    const Scan s = grid_scan(5, 20, [](double a, std::uint32_t, std::uint32_t c) {
        return (c < 10 ? 50.0 : 50.2) / std::cos(a);
    });
    const auto m = depth_discontinuities(s, 0.02);
    ASSERT_EQ(m.size(), s.size());
    // 9 and 10 straddle the step; 8 and 11 lie next to them.
    EXPECT_EQ(marked_columns(s, m, 2), (std::vector<int>{8, 9, 10, 11}));
    EXPECT_EQ(marked_columns(s, m, 0), (std::vector<int>{8, 9, 10, 11}));  // the grid's border
    EXPECT_EQ(depth_discontinuities(s, 0.02, 1), depth_discontinuities(s, 0.02, 2));
}

TEST(DepthDiscontinuities, AGrazingPlaneIsNotAnEdge) {
    // A plane seen 80° off its normal at 50 m: its ranges change by 6 cm a column, smoothly.
    const double alpha = 80 * M_PI / 180, d = 50 * std::cos(alpha);
    const Scan s = grid_scan(
        5, 40, [&](double a, std::uint32_t, std::uint32_t) { return d / std::cos(alpha - a); });
    EXPECT_GT(std::abs((s.xyz[1] - s.xyz[0]).norm()), 0.05);  // steps far beyond the jump
    const auto m = depth_discontinuities(s, 0.02);
    EXPECT_EQ(std::count(m.begin(), m.end(), 1), 0);
}

TEST(DepthDiscontinuities, APlaneAt87DegreesOnACoarseGridIsNotAnEdge) {
    // 45 m away, 87° off its normal, on a 0.1° grid: the ranges change by about 1.5 m a
    // column and their second differences reach the jump, but a slope, not a step.
    const double alpha = 87 * M_PI / 180, d = 45 * std::cos(alpha);
    const Scan s = grid_scan(
        3, 11, [&](double a, std::uint32_t, std::uint32_t) { return d / std::cos(alpha - a); },
        0.1);
    double largest = 0;
    for (std::size_t i = 1; i + 1 < 11; ++i)
        largest = std::max(
            largest, std::abs(s.xyz[i - 1].norm() - 2 * s.xyz[i].norm() + s.xyz[i + 1].norm()));
    EXPECT_GT(largest, 0.10);
    const auto m = depth_discontinuities(s, 0.10);
    EXPECT_EQ(std::count(m.begin(), m.end(), 1), 0);
}

TEST(DepthDiscontinuities, WithoutNeighboursOnlyTheBeamsAtTheStepAreMarked) {
    const Scan s = grid_scan(5, 20, [](double a, std::uint32_t, std::uint32_t c) {
        return (c < 10 ? 50.0 : 50.2) / std::cos(a);
    });
    const auto m = depth_discontinuities(s, 0.02, 0, false);
    EXPECT_EQ(marked_columns(s, m, 2), (std::vector<int>{9, 10}));
}

TEST(DepthDiscontinuities, ACellWithoutAReturnMarksItsNeighbours) {
    const Scan s = grid_scan(5, 20, [](double a, std::uint32_t r, std::uint32_t c) {
        return r == 2 && c == 12 ? std::nan("") : 50.0 / std::cos(a);
    });
    const auto m = depth_discontinuities(s, 0.02);
    // The beams beside the gap, and those next to them.
    EXPECT_EQ(marked_columns(s, m, 2), (std::vector<int>{10, 11, 13, 14}));
    EXPECT_EQ(marked_columns(s, m, 1), (std::vector<int>{11, 12, 13}));
    EXPECT_EQ(marked_columns(s, m, 3), (std::vector<int>{11, 12, 13}));
    EXPECT_EQ(marked_columns(s, m, 4), (std::vector<int>{12}));
}

TEST(DepthDiscontinuities, WithoutAGridNothingIsMarked) {
    Scan s = grid_scan(3, 3, [](double, std::uint32_t, std::uint32_t) { return 10.0; });
    EXPECT_THROW(depth_discontinuities(s, 0.0), Error);
    s.grid.reset();
    EXPECT_TRUE(depth_discontinuities(s, 0.02).empty());
}

// Nine points in a grid of 10¹⁰ cells (which the E57 reader refuses) are refused here too,
// rather than 40 GB allocated for the cells.
TEST(DepthDiscontinuities, AGridOfFarMoreCellsThanPointsIsRefused) {
    Scan s = grid_scan(3, 3, [](double, std::uint32_t, std::uint32_t) { return 10.0; });
    EXPECT_EQ(depth_discontinuities(s, 0.02).size(), 9u);
    s.grid->rows = s.grid->columns = 100'000;
    EXPECT_THROW(depth_discontinuities(s, 0.02), Error);
}

}  // namespace
}  // namespace tlsmon
