// Known answers for the keypoint outlier filters (step 5 of the Hochmoselbrücke method):
// planted outliers are removed by the filter meant for them and every inlier is kept
// (both counted), the ±π wrap of the horizontal angle and of the image columns, segments
// judged separately, and the rules for MAD = 0, tiny segments and non-finite input.
//
// Inliers are drawn uniformly: for a uniform distribution on [−a, a] the threshold
// 2 · 1.4826 · MAD = 1.48 a lies outside every inlier, so "all inliers kept" is a known
// answer, not a statistical one. Planted outliers lie 10 a away in one quantity only.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include "algorithms/keypoints/outlier_filters.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

using keypoints::KeypointMatch;
using keypoints::OutlierFilter;

// The differences of one match, each applied on top of fixed reference values.
struct Differences {
    double row = 0, column = 0, range = 0, azimuth = 0, elevation = 0;
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
};

double wrap_angle(double a) {  // into (−π, π]
    double r = std::remainder(a, 2 * std::numbers::pi);
    if (r <= -std::numbers::pi) r += 2 * std::numbers::pi;
    return r;
}

// Reference azimuth and column sit just below the wrap, so half the epoch's values wrap.
constexpr double kColumnsPerTurn = 10000;
constexpr double kReferenceColumn = kColumnsPerTurn - 0.1;
const double kReferenceAzimuth = std::numbers::pi - 5e-6;

KeypointMatch make_match(int segment, const Differences& x) {
    KeypointMatch m;
    m.segment = segment;
    m.reference_row = 500;
    m.row = 500 + x.row;
    m.reference_column = kReferenceColumn;
    m.column = std::fmod(kReferenceColumn + x.column + kColumnsPerTurn, kColumnsPerTurn);
    m.reference_range = 30;
    m.range = 30 + x.range;
    m.reference_azimuth = kReferenceAzimuth;
    m.azimuth = wrap_angle(kReferenceAzimuth + x.azimuth);
    m.reference_elevation = 0.2;
    m.elevation = 0.2 + x.elevation;
    m.reference_point = Eigen::Vector3d(12, -3, 8);
    m.point = m.reference_point + x.d;
    return m;
}

keypoints::OutlierParameters wrapping_parameters() {
    keypoints::OutlierParameters p;
    p.columns_per_turn = kColumnsPerTurn;
    return p;
}

TEST(KeypointOutlierFilters, PlantedOutliersGoToTheirOwnFilterAndAllInliersStay) {
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-1, 1);
    // Inlier amplitudes per quantity; the displacement is 10 mm down z plus noise, with
    // unequal lateral noise so the angle to the median vector stays well inside its bound.
    const double a_row = 0.3, a_column = 0.3, a_range = 0.002, a_angle = 2e-5;
    const double M = 0.010, ax = 0.001, ay = 0.0003, az = 0.0005;
    const auto inlier = [&] {
        Differences x;
        x.row = a_row * u(rng);
        x.column = a_column * u(rng);
        x.range = a_range * u(rng);
        x.azimuth = a_angle * u(rng);
        x.elevation = a_angle * u(rng);
        x.d = Eigen::Vector3d(ax * u(rng), ay * u(rng), -M + az * u(rng));
        return x;
    };
    std::vector<KeypointMatch> matches;
    std::vector<OutlierFilter> planted;
    for (int i = 0; i < 200; ++i) {
        matches.push_back(make_match(4, inlier()));
        planted.push_back(OutlierFilter::none);
    }
    // Three outliers per filter, 10 amplitudes off in that quantity only, either sign.
    for (int j = 0; j < 3; ++j) {
        const double s = j % 2 == 0 ? 10.0 : -10.0;
        const auto plant = [&](OutlierFilter f, auto change) {
            Differences x = inlier();
            change(x);
            matches.push_back(make_match(4, x));
            planted.push_back(f);
        };
        plant(OutlierFilter::row_difference, [&](Differences& x) { x.row += s * a_row; });
        plant(OutlierFilter::column_difference, [&](Differences& x) { x.column += s * a_column; });
        plant(OutlierFilter::range_difference, [&](Differences& x) { x.range += s * a_range; });
        plant(OutlierFilter::horizontal_angle_difference,
              [&](Differences& x) { x.azimuth += s * a_angle; });
        plant(OutlierFilter::vertical_angle_difference,
              [&](Differences& x) { x.elevation += s * a_angle; });
        plant(OutlierFilter::dx, [&](Differences& x) { x.d.x() += s * ax; });
        plant(OutlierFilter::dy, [&](Differences& x) { x.d.y() += s * ay; });
        plant(OutlierFilter::dz, [&](Differences& x) { x.d.z() += s * az; });
    }
    // Some inliers straddle the wrap (the test is void otherwise).
    int wrapped = 0, wrapped_columns = 0;
    for (const auto& m : matches) wrapped += m.azimuth < 0;
    for (const auto& m : matches) wrapped_columns += m.column < 1;
    ASSERT_GT(wrapped, 50);
    ASSERT_GT(wrapped_columns, 50);

    const auto result = keypoints::filter_outliers(matches, wrapping_parameters());
    ASSERT_EQ(result.removed_by.size(), matches.size());
    int kept_inliers = 0, removed_outliers = 0;
    for (std::size_t i = 0; i < matches.size(); ++i) {
        EXPECT_EQ(result.removed_by[i], planted[i])
            << "match " << i << " planted for '" << keypoints::outlier_filter_name(planted[i])
            << "' removed by '" << keypoints::outlier_filter_name(result.removed_by[i]) << "'";
        if (planted[i] == OutlierFilter::none && result.removed_by[i] == OutlierFilter::none)
            ++kept_inliers;
        if (planted[i] != OutlierFilter::none && result.removed_by[i] == planted[i])
            ++removed_outliers;
    }
    EXPECT_EQ(kept_inliers, 200);
    EXPECT_EQ(removed_outliers, 24);
    // The log: one segment, every filter run in order, three removals by each of the first 8.
    ASSERT_EQ(result.segments.size(), 1u);
    EXPECT_EQ(result.segments[0].segment, 4);
    const auto& steps = result.segments[0].steps;
    ASSERT_EQ(steps.size(), keypoints::kOutlierFilterOrder.size());
    for (std::size_t k = 0; k < steps.size(); ++k) {
        EXPECT_EQ(steps[k].filter, keypoints::kOutlierFilterOrder[k]);
        EXPECT_FALSE(steps[k].skipped);
        EXPECT_EQ(steps[k].removed, k < 8 ? 3u : 0u)
            << keypoints::outlier_filter_name(steps[k].filter);
    }
    // The median of dz is the planted −10 mm within the noise, and the threshold is 2σ.
    EXPECT_NEAR(steps[7].median, -M, az);
    EXPECT_DOUBLE_EQ(steps[7].threshold, 2 * steps[7].sigma);
    EXPECT_DOUBLE_EQ(steps[7].sigma, 1.4826 * steps[7].mad);
}

TEST(KeypointOutlierFilters, MagnitudeCatchesWhatNoComponentCan) {
    // Inliers point every way round a circle with lengths R(1 ± 10 %): each component spans
    // ±R (its threshold ≈ 2.1 R), the length only ±0.1 R. Vectors 1.5 R long stay inside
    // every component's bound but not the length's.
    const double R = 0.004;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<KeypointMatch> matches;
    for (int i = 0; i < 120; ++i) {
        const double theta = 2 * std::numbers::pi * i / 120.0, r = R * (1 + 0.1 * u(rng));
        Differences x;
        x.d = Eigen::Vector3d(r * std::cos(theta), r * std::sin(theta), 0);
        matches.push_back(make_match(0, x));
    }
    for (double theta : {0.3, 2.5}) {
        Differences x;
        x.d = 1.5 * R * Eigen::Vector3d(std::cos(theta), std::sin(theta), 0);
        matches.push_back(make_match(0, x));
    }
    const auto result = keypoints::filter_outliers(matches, wrapping_parameters());
    for (std::size_t i = 0; i < 120; ++i) EXPECT_EQ(result.removed_by[i], OutlierFilter::none);
    EXPECT_EQ(result.removed_by[120], OutlierFilter::magnitude);
    EXPECT_EQ(result.removed_by[121], OutlierFilter::magnitude);
}

TEST(KeypointOutlierFilters, AngleToTheMedianVectorCatchesWhatNoComponentCan) {
    // Inliers: 10 mm along x, lateral (y, z) offsets uniform in a disc of radius A = 1 mm.
    // Component bounds ≈ 1.2 A, angle bound ≈ 1.23 A / 10 mm above 0. Outliers at lateral
    // (±A, ±A): each component within its bound, the angle 1.41 A / 10 mm outside. The
    // inliers most parallel to the median (angle near 0, 5 % of them below median − bound)
    // stay: the angle is judged on one side.
    const double R = 0.010, A = 0.001;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u01(0, 1), u(-1, 1);
    std::vector<KeypointMatch> matches;
    for (int i = 0; i < 300; ++i) {
        const double r = A * std::sqrt(u01(rng)), psi = 2 * std::numbers::pi * u01(rng);
        Differences x;
        x.d = Eigen::Vector3d(R + 0.0002 * u(rng), r * std::cos(psi), r * std::sin(psi));
        matches.push_back(make_match(1, x));
    }
    for (double sy : {1.0, -1.0})
        for (double sz : {1.0, -1.0}) {
            Differences x;
            x.d = Eigen::Vector3d(R, sy * A, sz * A);
            matches.push_back(make_match(1, x));
        }
    const auto result = keypoints::filter_outliers(matches, wrapping_parameters());
    int kept = 0;
    for (std::size_t i = 0; i < 300; ++i) kept += result.removed_by[i] == OutlierFilter::none;
    EXPECT_EQ(kept, 300);
    for (std::size_t i = 300; i < 304; ++i)
        EXPECT_EQ(result.removed_by[i], OutlierFilter::angle_to_median) << i;
    for (const auto& step : result.segments[0].steps)
        EXPECT_EQ(step.removed, step.filter == OutlierFilter::angle_to_median ? 4u : 0u)
            << keypoints::outlier_filter_name(step.filter) << " median " << step.median
            << " threshold " << step.threshold;
}

TEST(KeypointOutlierFilters, SegmentsAreJudgedSeparately) {
    // Segment 0 moved +5 mm in z, segment 1 −5 mm, matches outside any segment +20 mm, each
    // ±0.5 mm (±0.15 mm in y). Pooled, a third of them would be outliers; per segment none is.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<KeypointMatch> matches;
    for (int i = 0; i < 240; ++i) {
        const int segment = i % 3 == 2 ? -1 : i % 3;
        const double dz = segment == 0 ? 0.005 : segment == 1 ? -0.005 : 0.020;
        Differences x;
        x.d = Eigen::Vector3d(0.0005 * u(rng), 0.00015 * u(rng), dz + 0.0005 * u(rng));
        matches.push_back(make_match(segment, x));
    }
    const auto result = keypoints::filter_outliers(matches);
    for (auto f : result.removed_by) EXPECT_EQ(f, OutlierFilter::none);
    ASSERT_EQ(result.segments.size(), 3u);
    EXPECT_EQ(result.segments[0].segment, -1);
    EXPECT_EQ(result.segments[1].segment, 0);
    EXPECT_EQ(result.segments[2].segment, 1);
    EXPECT_NEAR(result.segments[2].steps[7].median, -0.005, 0.0005);
}

TEST(KeypointOutlierFilters, MadZeroFallsBackToTheMeanDeviation) {
    // Whole-pixel row differences: 20 × 0, 5 × +1, 4 × −1 and one 40 px mismatch. MAD = 0;
    // mean absolute deviation (9 + 40)/30, σ = 1.2533 · 49/30, threshold 2σ = 4.09 px:
    // the 40 px goes, the ±1 px stay.
    std::vector<KeypointMatch> matches;
    const auto add = [&](double row, int n) {
        for (int i = 0; i < n; ++i) {
            Differences x;
            x.row = row;
            x.d = Eigen::Vector3d(0, 0, 0.001 * (i % 5));  // some spread: not all equal
            matches.push_back(make_match(2, x));
        }
    };
    add(0, 20);
    add(1, 5);
    add(-1, 4);
    add(40, 1);
    const auto result = keypoints::filter_outliers(matches);
    for (std::size_t i = 0; i + 1 < matches.size(); ++i)
        EXPECT_EQ(result.removed_by[i], OutlierFilter::none) << i;
    EXPECT_EQ(result.removed_by.back(), OutlierFilter::row_difference);
    const auto& row = result.segments[0].steps[0];
    EXPECT_TRUE(row.mad_was_zero);
    EXPECT_FALSE(row.skipped);
    EXPECT_DOUBLE_EQ(row.mad, 0.0);
    EXPECT_NEAR(row.sigma, 1.2533 * 49.0 / 30.0, 1e-12);
    EXPECT_NEAR(row.threshold, 2 * 1.2533 * 49.0 / 30.0, 1e-12);
    // All-equal quantities (every column difference is 0) remove nothing and say so.
    const auto& column = result.segments[0].steps[1];
    EXPECT_TRUE(column.skipped);
    EXPECT_EQ(column.removed, 0u);
    EXPECT_EQ(column.tested, 29u);
}

TEST(KeypointOutlierFilters, SpreadBelowTheNoiseIsFlooredNotCut) {
    // Two packagings of one scan: 40 vectors that agree to micrometres (26 within 0.1 µm, 14
    // at ±3 µm: MAD 0.1 µm) and one 30 mm mismatch. Without a noise model the threshold is
    // 2 · 1.48 · 0.1 µm and the 14 go; with the scanner's model the floor is
    // √2 · max(σ_r, r·σ_θ) at 30 m = √2 · 1.3 mm: only the mismatch goes.
    std::vector<KeypointMatch> matches;
    for (int i = 0; i < 40; ++i) {
        Differences x;
        const double dev = i < 26 ? 1e-7 * ((i % 3) - 1) : 3e-6 * (i % 2 ? 1 : -1);
        x.d = Eigen::Vector3d(0.004 + dev, 0.002, -0.001);
        x.range = 1e-6 * ((i % 3) - 1);
        matches.push_back(make_match(0, x));
    }
    Differences gross;
    gross.d = Eigen::Vector3d(0.034, 0.002, -0.001);
    matches.push_back(make_match(0, gross));

    const auto bare = keypoints::filter_outliers(matches);
    std::size_t bare_removed = 0;
    for (std::size_t i = 0; i + 1 < matches.size(); ++i)
        bare_removed += bare.removed_by[i] != OutlierFilter::none;
    EXPECT_GT(bare_removed, 10u);  // the defect the floor is for

    keypoints::OutlierParameters p;
    p.noise = ScannerNoise{};  // 1 mm + 10 ppm, 3″
    const auto floored = keypoints::filter_outliers(matches, p);
    for (std::size_t i = 0; i + 1 < matches.size(); ++i)
        EXPECT_EQ(floored.removed_by[i], OutlierFilter::none) << i;
    EXPECT_NE(floored.removed_by.back(), OutlierFilter::none);
    // The dx filter's σ is the floor: √2 · max(1 mm + 10 ppm · 30 m, 30 m · 3″).
    const auto& dx = floored.segments[0].steps[5];
    ASSERT_EQ(dx.filter, OutlierFilter::dx);
    const double single = std::max(0.0013, 30 * 3 * std::numbers::pi / (180 * 3600));
    EXPECT_NEAR(dx.floor, std::numbers::sqrt2 * single, 1e-12);
    EXPECT_TRUE(dx.floored);
    EXPECT_DOUBLE_EQ(dx.sigma, dx.floor);
    // The range difference's floor is √2 · σ_r(30 m).
    const auto& range = floored.segments[0].steps[2];
    EXPECT_NEAR(range.floor, std::numbers::sqrt2 * 0.0013, 1e-12);
    // A spread above the floor is the spread: the floor does not widen a noisy segment.
    for (auto& m : matches) m.point.y() += 0.01 * ((&m - matches.data()) % 7 - 3);
    const auto noisy = keypoints::filter_outliers(matches, p);
    EXPECT_FALSE(noisy.segments[0].steps[6].floored);  // dy: MAD of ±30 mm
    // A match estimated from a patch of 15 × 15 pixels: the floor is 15 times lower.
    p.averaged_pixels = 225;
    const auto patch = keypoints::filter_outliers(matches, p);
    EXPECT_NEAR(patch.segments[0].steps[2].floor, std::numbers::sqrt2 * 0.0013 / 15, 1e-12);
    p.averaged_pixels = 0.5;
    EXPECT_THROW(keypoints::filter_outliers(matches, p), Error);
    p.averaged_pixels = 1;
    // A negative noise is refused.
    p.noise->range_sigma_a = -1;
    EXPECT_THROW(keypoints::filter_outliers(matches, p), Error);
}

TEST(KeypointOutlierFilters, TinySegmentsAreLeftAlone) {
    // Two matches 1 m apart: no median or MAD can say which one is wrong.
    std::vector<KeypointMatch> matches;
    Differences x;
    matches.push_back(make_match(9, x));
    x.d = Eigen::Vector3d(1, 1, 1);
    x.row = 50;
    matches.push_back(make_match(9, x));
    const auto result = keypoints::filter_outliers(matches);
    EXPECT_EQ(result.removed_by[0], OutlierFilter::none);
    EXPECT_EQ(result.removed_by[1], OutlierFilter::none);
    for (const auto& step : result.segments[0].steps) {
        EXPECT_TRUE(step.skipped);
        EXPECT_EQ(step.tested, 2u);
    }
    EXPECT_TRUE(keypoints::filter_outliers(std::vector<KeypointMatch>{}).removed_by.empty());
}

TEST(KeypointOutlierFilters, NonFiniteInputNamesTheMatchAndField) {
    std::vector<KeypointMatch> matches(5, make_match(0, {}));
    matches[3].range = std::numeric_limits<double>::quiet_NaN();
    try {
        keypoints::filter_outliers(matches);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("keypoint match 3: range"), std::string::npos)
            << e.what();
    }
    matches[3].range = 30;
    matches[1].point.y() = std::numeric_limits<double>::infinity();
    EXPECT_THROW(keypoints::filter_outliers(matches), Error);
    keypoints::OutlierParameters bad;
    bad.k = 0;
    EXPECT_THROW(keypoints::filter_outliers({}, bad), Error);
}

TEST(KeypointOutlierFilters, NamesAreStableAndRoundTrip) {
    const std::vector<std::string> expected{"row_difference",
                                            "column_difference",
                                            "range_difference",
                                            "horizontal_angle_difference",
                                            "vertical_angle_difference",
                                            "dx",
                                            "dy",
                                            "dz",
                                            "magnitude",
                                            "angle_to_median"};
    for (std::size_t k = 0; k < expected.size(); ++k) {
        const OutlierFilter f = keypoints::kOutlierFilterOrder[k];
        EXPECT_EQ(keypoints::outlier_filter_name(f), expected[k]);
        EXPECT_EQ(keypoints::outlier_filter_from_name(expected[k]), f);
    }
    EXPECT_EQ(keypoints::outlier_filter_name(OutlierFilter::none), "");
    EXPECT_EQ(keypoints::outlier_filter_from_name(""), OutlierFilter::none);
    EXPECT_FALSE(keypoints::outlier_filter_from_name("range").has_value());
}

TEST(KeypointOutlierFilters, WrappedDifference) {
    const double pi = std::numbers::pi;
    EXPECT_NEAR(keypoints::periodic_difference(-pi + 0.01, pi - 0.01, 2 * pi), 0.02, 1e-12);
    EXPECT_NEAR(keypoints::periodic_difference(pi - 0.01, -pi + 0.01, 2 * pi), -0.02, 1e-12);
    EXPECT_DOUBLE_EQ(keypoints::periodic_difference(0.5, 9999.5, 10000), 1.0);
    EXPECT_DOUBLE_EQ(keypoints::periodic_difference(0.5, 9999.5, 0), -9999.0);
    EXPECT_DOUBLE_EQ(keypoints::periodic_difference(pi, 0, 2 * pi), pi);  // (−π, π]
}

}  // namespace
}  // namespace tlsmon::test
