// A surface that a voxel face cuts along itself (pipeline/pcl_adapter.hpp, voxel_means): only
// the count-weighted mean of the two sides is on it, and the ICP, weighing each pair by its
// voxel's points, measures a sub-millimetre move of densely sampled surfaces that the grid
// cuts at every phase.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "pipeline/icp_registration.hpp"

namespace tlsmon {
namespace {

constexpr double kSigma = 0.001;     // m, noise along the normal
constexpr double kSpacing = 0.0125;  // m: 64 points per 0.1 m voxel of a face

// A floor and two walls (4 m × 4 m × 1.5 m) set obliquely to the voxel grid (turned 10° about
// z, tilted 1° and 0.7°), so that the grid's faces cut them along themselves at every phase;
// each point off its surface by N(0, kSigma) along the normal, then taken into the epoch's
// frame by H⁻¹ (H: epoch -> reference).
const Eigen::Isometry3d kCornerPose =
    Eigen::Translation3d(0.013, 0.027, 0.004) *
    Eigen::AngleAxisd(10.0 * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()) *
    Eigen::AngleAxisd(1.0 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) *
    Eigen::AngleAxisd(0.7 * std::numbers::pi / 180, Eigen::Vector3d::UnitY());

Scan corner_scan(std::uint32_t seed, const Eigen::Isometry3d& H) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, kSigma);
    Scan s;
    s.pose = H.inverse() * kCornerPose * Eigen::Translation3d(6.0, 6.0, 1.5);
    const auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
        s.xyz.push_back(H.inverse() * kCornerPose * Eigen::Vector3d(p + noise(rng) * n));
    };
    const int n2 = static_cast<int>(4.0 / kSpacing), n1 = static_cast<int>(1.5 / kSpacing);
    for (int i = 1; i <= n2; ++i) {
        for (int j = 1; j <= n2; ++j)
            add({i * kSpacing, j * kSpacing, 0.0}, Eigen::Vector3d::UnitZ());
        for (int j = 1; j <= n1; ++j) {
            add({0.0, i * kSpacing, j * kSpacing}, Eigen::Vector3d::UnitX());
            add({i * kSpacing, 0.0, j * kSpacing}, Eigen::Vector3d::UnitY());
        }
    }
    return s;
}

// The mean of a voxel's points lies off a surface cut along itself; the count-weighted sum
// over both sides does not.
TEST(IcpVoxelCut, OnlyTheCountWeightedMeanOfACutFloorIsOnIt) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> noise(0.0, kSigma);
    const double delta = 0.0005;  // the floor half a σ above the voxels' face z = 0
    std::vector<Eigen::Vector3d> floor;
    for (int i = 0; i < 400; ++i)
        for (int j = 0; j < 400; ++j) floor.emplace_back(0.005 * i, 0.005 * j, delta + noise(rng));
    const VoxelMeans v = voxel_means(floor, 0.1);
    double sum = 0, weighted = 0, count = 0;
    for (std::size_t k = 0; k < v.points.size(); ++k) {
        sum += v.points[k].z();
        weighted += v.counts[k] * v.points[k].z();
        count += v.counts[k];
    }
    EXPECT_EQ(count, static_cast<double>(floor.size()));
    // 800 voxels, 400 above the face and 400 below it.
    EXPECT_EQ(v.points.size(), 800u);
    // E[z | z > 0] and E[z | z < 0] of N(δ, σ²) average to 0.19 mm, not 0.5 mm; the weighted
    // mean is the points' own (σ/√160000 = 0.0025 mm).
    EXPECT_NEAR(sum / v.points.size(), 0.000185, 0.00002);
    EXPECT_NEAR(weighted / count, delta, 0.00001);
}

// The ICP from the identity recovers a move of (0.4, −0.3, 0.5) mm and 30 µrad about z to
// within 0.03 mm over the corner, and its σ covers the error (with pairs of equal weight:
// 0.055 mm).
TEST(IcpVoxelCut, RecoversASubMillimetreMoveOfAnObliqueCorner) {
    const Eigen::Isometry3d H = Eigen::Translation3d(0.0004, -0.0003, 0.0005) *
                                Eigen::AngleAxisd(30e-6, Eigen::Vector3d::UnitZ());
    RegistrationConfig config;
    config.icp.mode = IcpMode::fallback;
    config.icp.regions.push_back(
        {"corner", Eigen::Vector3d(-1.5, -0.5, -0.5), Eigen::Vector3d(4.5, 5.5, 2.0)});
    const StableSurface surface =
        build_stable_surface(config.icp, {corner_scan(1, Eigen::Isometry3d::Identity())});
    const IcpMeasurement m =
        measure_icp(config, surface, {corner_scan(2, H)}, Eigen::Matrix4d::Identity());
    ASSERT_TRUE(m.transform) << m.refused;
    EXPECT_EQ(m.refused, "");
    const Eigen::Matrix4d E = m.transform->matrix();
    double worst = 0;
    for (const Eigen::Vector3d& c : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 4, 0),
                                     Eigen::Vector3d(4, 0, 1.5), Eigen::Vector3d(0, 4, 1.5)}) {
        const Eigen::Vector3d x = kCornerPose * c;
        const Eigen::Vector3d e = E.topLeftCorner<3, 3>() * x + E.topRightCorner<3, 1>() - H * x;
        worst = std::max(worst, e.norm());
    }
    std::printf("pairs %zu, worst error %.4f mm, tz %.4f mm (true 0.5), σ(tz) %.4f mm\n", m.pairs,
                1e3 * worst, 1e3 * E(2, 3), 1e3 * std::sqrt(m.transform->covariance(5, 5)));
    EXPECT_LT(worst, 0.00003);
    EXPECT_LE(std::fabs(E(2, 3) - 0.0005), 3.0 * std::sqrt(m.transform->covariance(5, 5)));
}

}  // namespace
}  // namespace tlsmon
