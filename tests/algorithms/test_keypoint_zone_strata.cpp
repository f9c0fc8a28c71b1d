// Known answers for a zone's stratified keypoint displacement (algorithms/keypoints/
// zone_strata.hpp): the wall cells a reference grid fills; strata weighted by their wall
// area, not by how many matches they hold; a stratum with too few matches joined to its
// neighbour; the standard error with the pooled spread as its floor.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "algorithms/keypoints/zone_strata.hpp"

namespace tlsmon::test {
namespace {

using keypoints::KeypointMatch;
using keypoints::OutlierFilter;

constexpr double kDeg = std::numbers::pi / 180;

// The wall y = 10 m, facing the scanner at the origin.
keypoints::WallFrame wall() {
    keypoints::WallFrame w;
    w.centroid = Eigen::Vector3d(0, 10, 0);
    w.normal = Eigen::Vector3d(0, -1, 0);
    w.horizontal = Eigen::Vector3d(1, 0, 0);
    w.vertical = Eigen::Vector3d(0, 0, 1);
    return w;
}

// `n` matches in the band of vertical angle `band` (5° bands), each moved `dx` along x,
// alternately ±`spread`.
void add(std::vector<KeypointMatch>& out, int band, int n, double dx, double spread) {
    for (int i = 0; i < n; ++i) {
        KeypointMatch m;
        m.segment = band;
        m.reference_point = Eigen::Vector3d(0.01 * i, 10, 0);
        m.point = m.reference_point + Eigen::Vector3d(dx + (i % 2 ? spread : -spread), 0, 0);
        out.push_back(m);
    }
}

TEST(KeypointZoneStrata, WallCellsCoverWhatTheReferenceSaw) {
    // A 0.95 m square of points every 0.05 m around the centroid: 4 × 4 cells of 0.25 m.
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j) points.emplace_back(-0.475 + 0.05 * i, 10, -0.475 + 0.05 * j);
    const auto cells = keypoints::wall_cell_centres(points, wall());
    EXPECT_EQ(cells.size(), 16u);
    for (const auto& c : cells) {
        EXPECT_NEAR(c.y(), 10, 1e-12);
        EXPECT_NEAR(std::abs(std::fmod(std::abs(c.x()), 0.25)), 0.125, 1e-12);
    }
    // Seen from 1 m below the wall's centre, a cell 0.125 m up is at atan(1.125 / 10).
    const auto angles =
        keypoints::vertical_angles(std::vector<Eigen::Vector3d>{{0, 10, 0.125}}, {0, 0, -1});
    EXPECT_NEAR(angles[0], std::atan2(1.125, 10.0), 1e-7);
    EXPECT_TRUE(keypoints::wall_cell_centres(points, keypoints::WallFrame{}).empty());
}

TEST(KeypointZoneStrata, StrataAreWeightedByTheirAreaNotByTheirMatches) {
    // Band 18 (0–5°): 30 cells, 40 matches moved 1 mm; band 19 (5–10°): 10 cells, 12 matches
    // moved 5 mm. The zone: 0.75 · 1 + 0.25 · 5 = 2 mm; the plain mean 1.92 mm.
    std::vector<KeypointMatch> matches;
    add(matches, 18, 40, 0.001, 0.0001);
    add(matches, 19, 12, 0.005, 0.0002);
    std::vector<float> cells(30, float(2.5 * kDeg));
    cells.resize(40, float(7.5 * kDeg));
    const std::vector<OutlierFilter> kept(matches.size(), OutlierFilter::none);
    keypoints::StratifiedParameters p;
    p.band_width = 5 * kDeg;
    const auto d = keypoints::stratified_displacement(matches, kept, wall(), cells, p);
    ASSERT_TRUE(d.defined()) << d.undefined_reason;
    EXPECT_EQ(d.count, 52u);
    EXPECT_NEAR(d.mean.x(), 0.002, 1e-12);
    EXPECT_NEAR(d.along[1], 0.002, 1e-12);  // h = x on this wall
    EXPECT_DOUBLE_EQ(d.covered_area_share, 1.0);
    // SE² = Σ w²·max(s², pooled)/n: the spreads are 0.1 and 0.2 mm (samples of ±),
    // pooled (39·s1² + 11·s2²)/50.
    const double s1 = 0.0001 * std::sqrt(40.0 / 39), s2 = 0.0002 * std::sqrt(12.0 / 11);
    const double pooled = (39 * s1 * s1 + 11 * s2 * s2) / 50;
    const double se = std::sqrt(0.75 * 0.75 * std::max(s1 * s1, pooled) / 40 +
                                0.25 * 0.25 * std::max(s2 * s2, pooled) / 12);
    EXPECT_NEAR(d.standard_error.x(), se, 1e-12);
    EXPECT_NEAR(d.along_standard_error[1], se, 1e-12);
}

TEST(KeypointZoneStrata, AStratumWithTooFewMatchesJoinsItsNeighbour) {
    // As above, and band 20 (10–15°): 5 cells, 3 matches moved 9 mm, too few for a stratum
    // of their own (10): it joins band 19, and band 21 (15–20°, 5 cells where nothing
    // matched) with them: 15 matches averaging 5.8 mm over 20 cells of the 50.
    std::vector<KeypointMatch> matches;
    add(matches, 18, 40, 0.001, 0.0001);
    add(matches, 19, 12, 0.005, 0.0);
    add(matches, 20, 3, 0.009, 0.0);
    std::vector<float> cells(30, float(2.5 * kDeg));
    cells.resize(40, float(7.5 * kDeg));
    cells.resize(45, float(12.5 * kDeg));
    cells.resize(50, float(17.5 * kDeg));
    const std::vector<OutlierFilter> kept(matches.size(), OutlierFilter::none);
    keypoints::StratifiedParameters p;
    p.band_width = 5 * kDeg;
    const auto d = keypoints::stratified_displacement(matches, kept, wall(), cells, p);
    ASSERT_TRUE(d.defined()) << d.undefined_reason;
    const double upper = (12 * 0.005 + 3 * 0.009) / 15;
    EXPECT_NEAR(d.mean.x(), 0.6 * 0.001 + 0.4 * upper, 1e-12);
    EXPECT_DOUBLE_EQ(d.covered_area_share, 0.9);  // band 21 saw no match
    // A removed match counts nowhere; fewer kept than min_matches: undefined.
    std::vector<OutlierFilter> removed(matches.size(), OutlierFilter::dx);
    for (int i = 0; i < 9; ++i) removed[static_cast<std::size_t>(i)] = OutlierFilter::none;
    EXPECT_FALSE(keypoints::stratified_displacement(matches, removed, wall(), cells, p).defined());
}

}  // namespace
}  // namespace tlsmon::test
