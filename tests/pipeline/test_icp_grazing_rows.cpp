// One scan row on grazing ground is no plane, however its ranges scatter
// (pipeline/pcl_adapter.hpp, surface_with_normals). A scanner reports each return on the beam
// it meant; an elevation error ε of the beam moves the hit along the ground, so the point
// slides along its nominal beam by r·ε·cot e (e the grazing angle). A row's points then lie
// in the row's cone of beams, spread along them as well as across, and their principal
// components find that cone, not the ground.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "pipeline/pcl_adapter.hpp"

namespace tlsmon {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kHeight = 2.0;             // m, the scanner above flat ground (z = 0)
constexpr double kElevation = -2.0 * kDeg;  // the first row's beams, 57 m away on the ground
constexpr double kRowStep = 0.005 * kDeg;   // the next row 0.14 m farther on the ground
constexpr double kSigmaAngle = 10.0 / 3600.0 * kDeg;  // the beam's elevation error
const Eigen::Vector3d kScanner(0.0, 0.0, kHeight);

// The rows' returns over 1° of azimuth (0.005° apart): each the range at which its perturbed
// beam meets the ground, reported on the nominal beam.
std::vector<Eigen::Vector3d> rows(int count, std::uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, kSigmaAngle);
    std::vector<Eigen::Vector3d> points;
    for (int k = 0; k < count; ++k) {
        const double e = kElevation - k * kRowStep;
        for (int c = 0; c < 200; ++c) {
            const double a = c * 0.005 * kDeg;
            const Eigen::Vector3d beam(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a),
                                       std::sin(e));
            const double range = kHeight / std::sin(-(e + noise(rng)));
            points.push_back(kScanner + range * beam);
        }
    }
    return points;
}

// The mean angle between the kept normals and the ground's, degrees.
double mean_tilt(const SurfaceSample& s) {
    double sum = 0;
    for (const auto& n : s.normals) sum += std::acos(std::abs(n.z())) / kDeg;
    return sum / static_cast<double>(s.normals.size());
}

TEST(IcpGrazingRows, OneRowScatteredAlongItsBeamsLooksLikeTheConeOfItsBeams) {
    const auto one = rows(1, 7);
    // The along-beam spread, r·σ_θ·cot e ≈ 80 mm, passes the shape tests of a plane.
    const SurfaceSample plain = surface_with_normals(one, 0.3, 0.02, kScanner);
    ASSERT_GT(plain.points.size(), one.size() / 2);
    // Its normals are the cone's, 2° off the ground's.
    EXPECT_NEAR(mean_tilt(plain), 2.0, 0.05);
    // The row's directions spread along the row only: no plane is left.
    const SurfaceSample tested = surface_with_normals(one, 0.3, 0.02, kScanner, {}, 1e-5);
    EXPECT_TRUE(tested.points.empty()) << tested.points.size() << " kept";
}

TEST(IcpGrazingRows, TwoRowsHoldAPlane) {
    const auto two = rows(2, 7);
    // The second row's beams are 0.005° lower: the directions spread 0.0025° (4.4·10⁻⁵ rad).
    const SurfaceSample tested = surface_with_normals(two, 0.3, 0.02, kScanner, {}, 1e-5);
    ASSERT_GT(tested.points.size(), two.size() / 2);
    // The second row pulls the plane towards the ground, but the spread along the beams (80 mm
    // against rows 0.14 m apart; 6.5 mm against 0.1 m at `pier`'s own step) still tilts it.
    const SurfaceSample one_row = surface_with_normals(rows(1, 7), 0.3, 0.02, kScanner);
    EXPECT_LT(mean_tilt(tested), 0.8 * mean_tilt(one_row));
    const SurfaceSample wider = surface_with_normals(two, 0.3, 0.02, kScanner, {}, 1e-4);
    EXPECT_TRUE(wider.points.empty()) << "a spread below the limit keeps no plane";
}

}  // namespace
}  // namespace tlsmon
