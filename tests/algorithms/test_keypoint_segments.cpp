// Known answers for a segment's keypoint displacement (step 6 of the Hochmoselbrücke
// method): a planar wall at a known orientation moved by a known vector, with normally
// distributed noise on every match: the mean vector and its components along the wall's
// normal and along the surface within 3σ/√n of the truth, the spreads within 3 of their
// own standard errors; the wall frame's directions on walls where they are known exactly;
// undefined segments and walls; the vertical-angle bands.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "algorithms/keypoints/segment_displacement.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

using keypoints::KeypointMatch;
using keypoints::OutlierFilter;

constexpr double kDeg = std::numbers::pi / 180;

// A tilted wall 20 m in front of the scanner (at the origin), facing it: its normal points
// to the scanner, 15° off vertical.
struct Wall {
    Eigen::Vector3d normal, horizontal, vertical, centre;
};
Wall tilted_wall() {
    Wall w;
    w.normal = Eigen::Vector3d(-std::cos(15 * kDeg) * std::cos(40 * kDeg),
                               -std::cos(15 * kDeg) * std::sin(40 * kDeg), std::sin(15 * kDeg));
    w.horizontal = Eigen::Vector3d::UnitZ().cross(w.normal).normalized();
    w.vertical = w.normal.cross(w.horizontal);
    w.centre = -20 * w.normal + Eigen::Vector3d(0, 0, 6);
    return w;
}

struct Scene {
    std::vector<KeypointMatch> matches;
    std::vector<OutlierFilter> removed_by;
};

// n matches on the wall (10 m × 5 m, 1 mm off-plane noise) moved by `motion` plus N(0, σ)
// per component, in `segment`.
void add_wall(Scene& scene, const Wall& w, const Eigen::Vector3d& motion, double sigma, int n,
              int segment, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::normal_distribution<double> noise(0, sigma), off_plane(0, 0.001);
    for (int i = 0; i < n; ++i) {
        KeypointMatch m;
        m.segment = segment;
        m.reference_point = w.centre + 5 * u(rng) * w.horizontal + 2.5 * u(rng) * w.vertical +
                            off_plane(rng) * w.normal;
        m.point = m.reference_point + motion + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
        scene.matches.push_back(m);
        scene.removed_by.push_back(OutlierFilter::none);
    }
}

keypoints::SegmentParameters towards_scanner() {
    keypoints::SegmentParameters p;
    p.orientation = m3c2::Orientation::towards(Eigen::Vector3d::Zero());
    return p;
}

TEST(KeypointSegments, MeanAndWallComponentsOfAKnownMotionOnATiltedWall) {
    const Wall w = tilted_wall();
    // 2 mm towards the scanner, 3 mm to the right along the wall, 1.5 mm down it.
    const Eigen::Vector3d along_truth(0.002, 0.003, -0.0015);
    const Eigen::Vector3d motion =
        along_truth[0] * w.normal + along_truth[1] * w.horizontal + along_truth[2] * w.vertical;
    const double sigma = 0.001;
    const int n = 400;
    std::mt19937 rng(21);
    Scene scene;
    add_wall(scene, w, motion, sigma, n, 3, rng);
    // Gross vectors the filters removed, and another segment's matches: both left out.
    add_wall(scene, w, Eigen::Vector3d(0.05, -0.04, 0.03), sigma, 30, 3, rng);
    for (int i = n; i < n + 30; ++i) scene.removed_by[i] = OutlierFilter::dx;
    add_wall(scene, w, -motion, sigma, 50, 8, rng);

    const auto s =
        keypoints::segment_displacement(scene.matches, scene.removed_by, 3, towards_scanner());
    ASSERT_TRUE(s.defined()) << s.undefined_reason;
    EXPECT_EQ(s.segment, 3);
    EXPECT_EQ(s.matches, 430u);
    EXPECT_EQ(s.count, 400u);
    const double bound = 3 * sigma / std::sqrt(n);  // 0.15 mm
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(s.mean[k], motion[k], bound) << "component " << k;
        // The spread of a sample standard deviation is σ/√(2(n − 1)).
        EXPECT_NEAR(s.std_dev[k], sigma, 3 * sigma / std::sqrt(2.0 * (n - 1))) << k;
        EXPECT_NEAR(s.along[k], along_truth[k], bound) << "wall component " << k;
        // Isotropic noise: each wall component spreads by σ too.
        EXPECT_NEAR(s.along_std_dev[k], sigma, 3 * sigma / std::sqrt(2.0 * (n - 1))) << k;
    }
    // The kept mean is a trimmed mean: its standard error from the Winsorized values of all
    // 430 matches of the segment (the 30 removed ones at the kept extremes), each its own
    // cluster: √(N/(N − 1) · Σ (W − W̄)²) / n.
    Eigen::Vector3d low = Eigen::Vector3d::Constant(1.0), high = -low;
    for (int i = 0; i < n; ++i) {
        low = low.cwiseMin(scene.matches[i].displacement());
        high = high.cwiseMax(scene.matches[i].displacement());
    }
    std::vector<Eigen::Vector3d> winsorized;
    Eigen::Vector3d w_mean = Eigen::Vector3d::Zero();
    for (int i = 0; i < n + 30; ++i) {
        winsorized.push_back(scene.matches[i].displacement().cwiseMax(low).cwiseMin(high));
        w_mean += winsorized.back() / (n + 30.0);
    }
    Eigen::Vector3d squares = Eigen::Vector3d::Zero();
    for (const auto& x : winsorized) squares += (x - w_mean).cwiseAbs2();
    const Eigen::Vector3d se = (squares * (n + 30.0) / (n + 29.0)).cwiseSqrt() / n;
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(s.standard_error[k], se[k], 1e-15) << k;
        // The removed 7 % at the extremes: more than the kept spread over √n claims.
        EXPECT_GT(s.standard_error[k], 1.1 * s.std_dev[k] / std::sqrt(n)) << k;
    }
    EXPECT_NEAR(s.along_normal(), 0.002, bound);
    EXPECT_NEAR(s.along_surface_horizontal(), 0.003, bound);
    EXPECT_NEAR(s.along_surface_vertical(), -0.0015, bound);
    // The fitted frame is the wall's: 1 mm off-plane noise over 10 m × 5 m tilts it < 0.01°.
    ASSERT_TRUE(s.wall.defined());
    EXPECT_GT(s.wall.normal.dot(w.normal), std::cos(0.01 * kDeg));
    EXPECT_GT(s.wall.horizontal.dot(w.horizontal), std::cos(0.01 * kDeg));
    EXPECT_GT(s.wall.vertical.dot(w.vertical), std::cos(0.01 * kDeg));
    EXPECT_NEAR(s.wall.rms, 0.001, 0.0002);
    EXPECT_FALSE(s.wall.horizontal_surface);
}

// Nothing removed and each match its own cluster: the standard error is s/√n.
TEST(KeypointSegments, WithNothingRemovedTheStandardErrorIsTheSpreadOverRootN) {
    std::mt19937 rng(5);
    Scene scene;
    add_wall(scene, tilted_wall(), Eigen::Vector3d(0.001, 0, 0), 0.001, 200, 0, rng);
    const auto s =
        keypoints::segment_displacement(scene.matches, scene.removed_by, 0, towards_scanner());
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(s.standard_error[k], s.std_dev[k] / std::sqrt(200.0), 1e-15);
        EXPECT_NEAR(s.along_standard_error[k], s.along_std_dev[k] / std::sqrt(200.0), 1e-15);
    }
}

// The outlier filters keep the values near the sample's own median, so the kept mean scatters
// more than the kept values' spread over √n says. Over 2000 segments of 300 matches (N(0, 1 mm)
// with 10 % from N(0, 3 mm), as refined matches scatter), each trimmed at 2 · 1.4826 · MAD
// about its median in x: the standard error is honest (RMS of error / SE within 10 % of 1;
// 1.05 with this seed, an asymptotic formula on 300 matches), while s/√n of the kept values
// is too small (1.25).
TEST(KeypointSegments, TheStandardErrorCoversTheTrimmedMean) {
    std::mt19937 rng(17);
    std::normal_distribution<double> core(0, 0.001), tail(0, 0.003);
    std::uniform_real_distribution<double> share(0, 1);
    const Wall w = tilted_wall();
    double z2 = 0, naive_z2 = 0;
    const int trials = 2000, n = 300;
    for (int t = 0; t < trials; ++t) {
        Scene scene;
        std::vector<double> x;
        for (int i = 0; i < n; ++i) {
            KeypointMatch m;
            m.segment = 0;
            m.reference_point = w.centre + 0.01 * i * w.horizontal + 0.01 * (i % 7) * w.vertical;
            const double e = share(rng) < 0.1 ? tail(rng) : core(rng);
            m.point = m.reference_point + Eigen::Vector3d(e, 0, 0);
            x.push_back(e);
            scene.matches.push_back(m);
        }
        std::vector<double> sorted = x;
        std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
        const double median = sorted[n / 2];
        for (auto& v : sorted) v = std::abs(v - median);
        std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
        const double threshold = 2 * 1.4826 * sorted[n / 2];
        for (int i = 0; i < n; ++i)
            scene.removed_by.push_back(std::abs(x[static_cast<std::size_t>(i)] - median) > threshold
                                           ? OutlierFilter::dx
                                           : OutlierFilter::none);
        const auto s =
            keypoints::segment_displacement(scene.matches, scene.removed_by, 0, towards_scanner());
        ASSERT_TRUE(s.defined());
        z2 += std::pow(s.mean.x() / s.standard_error.x(), 2);
        naive_z2 += std::pow(s.mean.x() / (s.std_dev.x() / std::sqrt(double(s.count))), 2);
    }
    const double rms = std::sqrt(z2 / trials), naive = std::sqrt(naive_z2 / trials);
    std::printf("RMS(error / SE): trimmed mean's %.3f, kept spread over √n %.3f\n", rms, naive);
    EXPECT_NEAR(rms, 1.0, 0.1);
    EXPECT_GT(naive, 1.15);
}

// Matches anchored within one refinement patch err together: three keypoints of one feature
// count as one cluster, so 150 features seen three times each give the standard error of 150.
TEST(KeypointSegments, MatchesOfOnePatchAreOneCluster) {
    std::mt19937 rng(8);
    Scene unique, tripled;
    add_wall(unique, tilted_wall(), Eigen::Vector3d::Zero(), 0.001, 150, 0, rng);
    for (std::size_t i = 0; i < unique.matches.size(); ++i) {
        KeypointMatch m = unique.matches[i];
        m.reference_row = 30.0 * double(i / 30) + 1, m.reference_column = 30.0 * double(i % 30);
        for (int copy = 0; copy < 3; ++copy) {
            m.reference_column += 1;  // columns 1–3 of a 15-pixel cell
            tripled.matches.push_back(m);
            tripled.removed_by.push_back(OutlierFilter::none);
        }
    }
    keypoints::SegmentParameters p = towards_scanner();
    const auto one = keypoints::segment_displacement(unique.matches, unique.removed_by, 0, p);
    const auto each = keypoints::segment_displacement(tripled.matches, tripled.removed_by, 0, p);
    p.cluster_px = 15;
    const auto clustered =
        keypoints::segment_displacement(tripled.matches, tripled.removed_by, 0, p);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(clustered.standard_error[k], one.standard_error[k], 1e-15) << k;
        EXPECT_NEAR(each.standard_error[k] * std::sqrt(3.0), one.standard_error[k],
                    0.01 * one.standard_error[k])
            << k;
    }
}

TEST(KeypointSegments, AGivenWallFrameIsUsedAsIs) {
    const Wall w = tilted_wall();
    Scene scene;
    std::mt19937 rng(4);
    add_wall(scene, w, 0.004 * w.horizontal, 0.0, 20, 0, rng);  // no noise: exact answers
    keypoints::WallFrame frame;
    frame.centroid = w.centre;
    frame.normal = w.normal;
    frame.horizontal = w.horizontal;
    frame.vertical = w.vertical;
    const auto s = keypoints::segment_displacement(scene.matches, scene.removed_by, 0,
                                                   towards_scanner(), frame);
    ASSERT_TRUE(s.defined());
    EXPECT_NEAR(s.along[0], 0.0, 1e-15);
    EXPECT_NEAR(s.along[1], 0.004, 1e-15);
    EXPECT_NEAR(s.along[2], 0.0, 1e-15);
    // Equal vectors (up to rounding of point − reference point): spreads 0, not NaN.
    EXPECT_NEAR(s.std_dev.norm(), 0.0, 1e-15);
    EXPECT_NEAR(s.along_std_dev.norm(), 0.0, 1e-15);
}

TEST(KeypointSegments, WallDirectionsOnAWallFacingTheScanner) {
    // The plane y = 10 seen from the origin: normal −y (towards the scanner), horizontal +x
    // (to the right, looking along +y with z up), vertical +z.
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 4; ++j) points.emplace_back(-2 + i, 10, 1 + j);
    const auto f =
        keypoints::fit_wall_frame(points, m3c2::Orientation::towards(Eigen::Vector3d::Zero()));
    ASSERT_TRUE(f.defined());
    EXPECT_NEAR((f.normal - Eigen::Vector3d(0, -1, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((f.horizontal - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((f.vertical - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-12);
    EXPECT_NEAR(f.rms, 0, 1e-12);
    EXPECT_NEAR((f.centroid - Eigen::Vector3d(0, 10, 2.5)).norm(), 0, 1e-12);
    // Oriented by a fixed vector instead: +y.
    const auto g = keypoints::fit_wall_frame(points, m3c2::Orientation::along({0, 1, 0}));
    EXPECT_NEAR((g.normal - Eigen::Vector3d(0, 1, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((g.horizontal - Eigen::Vector3d(-1, 0, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((g.vertical - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-12);
}

TEST(KeypointSegments, AHorizontalSurfaceTakesTheXAxisAsItsHorizontal) {
    // A deck soffit at z = 5 above the scanner: normal −z, h = x, v = n × h = −y.
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) points.emplace_back(i, j, 5);
    const auto f =
        keypoints::fit_wall_frame(points, m3c2::Orientation::towards(Eigen::Vector3d::Zero()));
    ASSERT_TRUE(f.defined());
    EXPECT_TRUE(f.horizontal_surface);
    EXPECT_NEAR((f.normal - Eigen::Vector3d(0, 0, -1)).norm(), 0, 1e-12);
    EXPECT_NEAR((f.horizontal - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((f.vertical - Eigen::Vector3d(0, -1, 0)).norm(), 0, 1e-12);
}

TEST(KeypointSegments, TooFewMatchesLeaveTheSegmentUndefinedNotNaNSilently) {
    const Wall w = tilted_wall();
    Scene scene;
    std::mt19937 rng(8);
    add_wall(scene, w, Eigen::Vector3d(0.001, 0, 0), 0.001, 12, 1, rng);
    scene.removed_by[0] = scene.removed_by[5] = scene.removed_by[7] = OutlierFilter::magnitude;
    const auto s = keypoints::segment_displacement(scene.matches, scene.removed_by, 1,
                                                   towards_scanner());  // 9 kept < 10
    EXPECT_FALSE(s.defined());
    EXPECT_EQ(s.count, 9u);
    EXPECT_EQ(s.matches, 12u);
    EXPECT_NE(s.undefined_reason.find("fewer than min_matches 10"), std::string::npos)
        << s.undefined_reason;
    EXPECT_TRUE(std::isnan(s.mean.x()));
    EXPECT_TRUE(std::isnan(s.along_normal()));
    // A segment with no matches at all.
    EXPECT_FALSE(
        keypoints::segment_displacement(scene.matches, scene.removed_by, 42, towards_scanner())
            .defined());
    // With min_matches 9 the same segment is defined.
    auto p = towards_scanner();
    p.min_matches = 9;
    EXPECT_TRUE(keypoints::segment_displacement(scene.matches, scene.removed_by, 1, p).defined());
    p.min_matches = 1;
    EXPECT_THROW(keypoints::segment_displacement(scene.matches, scene.removed_by, 1, p), Error);
    scene.removed_by.pop_back();
    EXPECT_THROW(
        keypoints::segment_displacement(scene.matches, scene.removed_by, 1, towards_scanner()),
        Error);
}

TEST(KeypointSegments, CollinearReferencePointsLeaveTheWallUndefined) {
    // Keypoints along one edge: the mean vector is known, the plane is not.
    Scene scene;
    for (int i = 0; i < 15; ++i) {
        KeypointMatch m;
        m.segment = 0;
        m.reference_point = Eigen::Vector3d(i * 0.5, 10, 3);
        m.point = m.reference_point + Eigen::Vector3d(0.001, 0.002, -0.003 + 0.0001 * (i % 3));
        scene.matches.push_back(m);
        scene.removed_by.push_back(OutlierFilter::none);
    }
    const auto s =
        keypoints::segment_displacement(scene.matches, scene.removed_by, 0, towards_scanner());
    ASSERT_TRUE(s.defined());
    EXPECT_NEAR(s.mean.x(), 0.001, 1e-15);
    EXPECT_NEAR(s.mean.y(), 0.002, 1e-15);
    EXPECT_NEAR(s.mean.z(), -0.003 + 0.0001, 1e-15);  // i % 3 averages to 1 over 15
    EXPECT_FALSE(s.wall.defined());
    EXPECT_NE(s.wall.undefined_reason.find("one line"), std::string::npos);
    EXPECT_TRUE(std::isnan(s.along_normal()));
    const std::vector<Eigen::Vector3d> two{{0, 0, 0}, {1, 0, 0}};
    EXPECT_FALSE(keypoints::fit_wall_frame(two, m3c2::Orientation{}).defined());
}

TEST(KeypointSegments, VerticalAngleBands) {
    const double w = 5 * kDeg;
    EXPECT_EQ(keypoints::vertical_angle_band(-90 * kDeg, w), 0);
    EXPECT_EQ(keypoints::vertical_angle_band(-85.001 * kDeg, w), 0);
    EXPECT_EQ(keypoints::vertical_angle_band(-84.999 * kDeg, w), 1);
    EXPECT_EQ(keypoints::vertical_angle_band(-0.001 * kDeg, w), 17);
    EXPECT_EQ(keypoints::vertical_angle_band(0.0, w), 18);
    EXPECT_EQ(keypoints::vertical_angle_band(4.999 * kDeg, w), 18);
    EXPECT_EQ(keypoints::vertical_angle_band(89.999 * kDeg, w), 35);
    EXPECT_EQ(keypoints::vertical_angle_band(90 * kDeg, w), 35);  // the top edge: last band
    // A width that does not divide 180°: 26 bands of 7°, the last one short.
    EXPECT_EQ(keypoints::vertical_angle_band(90 * kDeg, 7 * kDeg), 25);
    const auto [lo, hi] = keypoints::vertical_angle_band_bounds(18, w);
    EXPECT_NEAR(lo, 0, 1e-15);
    EXPECT_NEAR(hi, 5 * kDeg, 1e-15);
    EXPECT_THROW(keypoints::vertical_angle_band(0.0, 0.0), Error);
    EXPECT_THROW(keypoints::vertical_angle_band(91 * kDeg, w), Error);
    EXPECT_THROW(keypoints::vertical_angle_band(std::numeric_limits<double>::quiet_NaN(), w),
                 Error);

    std::vector<KeypointMatch> matches(3);
    matches[0].reference_elevation = 12 * kDeg;
    matches[0].elevation = 30 * kDeg;  // the epoch's angle does not decide the band
    matches[1].reference_elevation = -3 * kDeg;
    matches[2].reference_elevation = 44.9 * kDeg;
    EXPECT_EQ(keypoints::vertical_angle_bands(matches), (std::vector<int>{20, 17, 26}));
    matches[1].reference_elevation = 2.0;  // rad, above the zenith
    try {
        keypoints::vertical_angle_bands(matches);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("keypoint match 1"), std::string::npos);
    }
}

}  // namespace
}  // namespace tlsmon::test
