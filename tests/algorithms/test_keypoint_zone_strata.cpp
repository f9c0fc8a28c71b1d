// Known answers for a zone's stratified keypoint displacement (algorithms/keypoints/
// zone_strata.hpp): the wall cells a reference grid fills; strata weighted by their wall
// area, not by how many matches they hold; a stratum with too few matches joined to its
// neighbour; the standard error with the pooled spread as its floor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

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

TEST(KeypointZoneStrata, AStratumsMeanStandsForItsAreaNotForWhereItsMatchesCrowd) {
    // One band (0–5°) of the wall seen from the origin: 40 cells evenly from 0.01 to 0.79 m
    // up, 20 matches crowded in its lowest 0.3 m, the displacement along x growing with the
    // vertical angle e as 1 mm + 20 mm/rad·e (a face that bends). The stratum's value is the
    // field's mean over the cells, not over the matches: 1 mm + 20 mm/rad·Ē.
    const auto field = [](double e) { return 0.001 + 0.02 * e; };
    std::vector<KeypointMatch> matches;
    double matches_elevation = 0;
    for (int i = 0; i < 20; ++i) {
        KeypointMatch m;
        m.segment = 18;
        m.reference_point = Eigen::Vector3d(0, 10, 0.015 * i);
        const double e = std::atan2(0.015 * i, 10.0);
        m.point = m.reference_point + Eigen::Vector3d(field(e), 0, 0);
        matches.push_back(m);
        matches_elevation += e / 20;
    }
    std::vector<float> cells;
    double cells_elevation = 0;
    for (int j = 0; j < 40; ++j) {
        cells.push_back(float(std::atan2(0.01 + 0.02 * j, 10.0)));
        cells_elevation += double(cells.back()) / 40;
    }
    const std::vector<OutlierFilter> kept(matches.size(), OutlierFilter::none);
    keypoints::StratifiedParameters p;
    p.band_width = 5 * kDeg;
    const auto d = keypoints::stratified_displacement(matches, kept, wall(), cells, p);
    ASSERT_TRUE(d.defined()) << d.undefined_reason;
    EXPECT_NEAR(d.mean.x(), field(cells_elevation), 1e-12);
    EXPECT_NEAR(d.along[1], field(cells_elevation), 1e-12);
    // The plain mean, where the matches are, is 0.5 mm short of it.
    EXPECT_NEAR(field(cells_elevation) - field(matches_elevation), 0.02 * 0.025, 0.00002);
    // Matches exactly on the line: their residuals about it are nil, and so is the σ (the
    // change across the stratum is not scatter).
    EXPECT_NEAR(d.standard_error.x(), 0.0, 1e-12);
}

TEST(KeypointZoneStrata, TheRegressionsStandardErrorCoversItsError) {
    // The same band, 40 matches (as a far zone holds) at random heights in its lowest 0.3 m,
    // 0.5 mm of noise per component, the field changing by 16 mm across the band (0.2 m/rad):
    // over 2000 draws the value is unbiased and its standard error (the mean's about the line
    // and the slope's part) honest, where the plain mean misses by 5 mm.
    const auto field = [](double e) { return 0.001 + 0.2 * e; };
    std::vector<float> cells;
    double cells_elevation = 0;
    for (int j = 0; j < 40; ++j) {
        cells.push_back(float(std::atan2(0.01 + 0.02 * j, 10.0)));
        cells_elevation += double(cells.back()) / 40;
    }
    keypoints::StratifiedParameters p;
    p.band_width = 5 * kDeg;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> height(0.0, 0.3);
    std::normal_distribution<double> noise(0.0, 0.0005);
    double sum = 0, sum_z2 = 0, plain = 0, covered = 0;
    constexpr int kDraws = 2000;
    constexpr int kMatches = 40;
    for (int draw = 0; draw < kDraws; ++draw) {
        std::vector<KeypointMatch> matches;
        double mean = 0;
        for (int i = 0; i < kMatches; ++i) {
            KeypointMatch m;
            m.segment = 18;
            m.reference_point = Eigen::Vector3d(0, 10, height(rng));
            const double e = std::atan2(m.reference_point.z(), 10.0);
            m.point = m.reference_point + Eigen::Vector3d(field(e) + noise(rng), noise(rng), 0);
            matches.push_back(m);
            mean += m.displacement().x() / kMatches;
        }
        const std::vector<OutlierFilter> kept(matches.size(), OutlierFilter::none);
        const auto d = keypoints::stratified_displacement(matches, kept, wall(), cells, p);
        ASSERT_TRUE(d.defined()) << d.undefined_reason;
        const double error = d.mean.x() - field(cells_elevation);
        sum += error;
        sum_z2 += std::pow(error / d.standard_error.x(), 2);
        covered += std::abs(error) <= 1.96 * d.standard_error.x() ? 1.0 / kDraws : 0.0;
        plain += (mean - field(cells_elevation)) / kDraws;
    }
    EXPECT_LT(std::abs(sum / kDraws), 0.00003);  // 3 standard errors of the 2000 draws' mean
    std::printf("40 matches: RMS(error/SE) %.3f, within 1.96 SE %.1f %%, plain mean off %.2f mm\n",
                std::sqrt(sum_z2 / kDraws), 100 * covered, 1e3 * plain);
    EXPECT_NEAR(std::sqrt(sum_z2 / kDraws), 1.0, 0.08);
    EXPECT_GT(covered, 0.93);
    EXPECT_LT(covered, 0.97);
    EXPECT_LT(plain, -0.002);
}

}  // namespace
}  // namespace tlsmon::test
