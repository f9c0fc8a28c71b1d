// A supervoxel as a patch of plane and its change (algorithms/registration/supervoxel_change.hpp)
// against known answers: a noisy square of a tilted plane gives back its normal, its noise
// and its centroid; the change of points shifted along the normal is the shift, and its LoD
// is z·√(s_e²/m_e + s_r²/m + σ_T²) computed by hand.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "algorithms/registration/supervoxel_change.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {
namespace {

struct NoisyPlane {
    std::vector<Eigen::Vector3d> points;
    Eigen::Vector3d normal;
};

// A 1 m square of the plane through (10, 20, 1) with the normal (0.6, −0.8, 0) turned 10°
// upwards, sampled every 5 cm, σ along the normal `sigma`; shifted by `shift` along it.
NoisyPlane noisy_plane(double sigma, double shift, unsigned seed) {
    const Eigen::Vector3d n =
        Eigen::Vector3d(0.6 * std::cos(0.1745), -0.8 * std::cos(0.1745), std::sin(0.1745))
            .normalized();
    const Eigen::Vector3d u = n.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d v = n.cross(u);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    NoisyPlane p{{}, n};
    for (int i = 0; i < 20; ++i) {
        for (int j = 0; j < 20; ++j) {
            p.points.push_back(Eigen::Vector3d(10, 20, 1) + (0.05 * i - 0.475) * u +
                               (0.05 * j - 0.475) * v + (shift + noise(rng)) * n);
        }
    }
    return p;
}

TEST(SupervoxelChange, APatchGivesBackItsPlaneAndItsNoise) {
    const NoisyPlane p = noisy_plane(0.001, 0.0, 1);
    // The viewpoint on the normal's side: the normal is turned towards it.
    const SupervoxelPatch q = patch_of(p.points, Eigen::Vector3d(10, 20, 1) + 30 * p.normal);
    EXPECT_EQ(q.samples, 400u);
    EXPECT_GT(q.normal.dot(p.normal), std::cos(0.5 * M_PI / 180));  // within 0.5°
    EXPECT_NEAR(q.centroid.x(), 10.0, 0.0005);
    EXPECT_NEAR(q.centroid.y(), 20.0, 0.0005);
    EXPECT_NEAR(q.sigma, 0.001, 0.0002);
    EXPECT_LT(q.surface_variation, 1e-4);
    EXPECT_GT(q.spread, 0.9);  // a square: both in-plane directions alike
    // Seen from the other side, the normal turns round.
    const SupervoxelPatch back = patch_of(p.points, Eigen::Vector3d(10, 20, 1) - 30 * p.normal);
    EXPECT_LT(back.normal.dot(p.normal), -0.99);
}

TEST(SupervoxelChange, AShiftAlongTheNormalIsTheChangeWithTheLodOfItsParts) {
    const NoisyPlane ref = noisy_plane(0.001, 0.0, 2);
    const NoisyPlane moved = noisy_plane(0.002, 0.003, 3);
    const SupervoxelPatch q = patch_of(ref.points, Eigen::Vector3d(10, 20, 1) + 30 * ref.normal);
    std::vector<double> d;
    for (const auto& x : moved.points) d.push_back(q.normal.dot(x - q.centroid));
    const double sigma_T = 0.0002;
    const SupervoxelChange c = change_of(q, d, sigma_T, 1.96);
    EXPECT_NEAR(c.change, 0.003, 0.0003);
    EXPECT_NEAR(c.sigma_epoch, 0.002, 0.0002);
    const double lod = 1.96 * std::sqrt(c.sigma_epoch * c.sigma_epoch / 400 +
                                        q.sigma * q.sigma / 400 + sigma_T * sigma_T);
    EXPECT_NEAR(c.lod, lod, 1e-12);
    EXPECT_TRUE(c.significant());
    // Unmoved: not significant at 95 % for this seed, and the LoD of the same size.
    const NoisyPlane still = noisy_plane(0.002, 0.0, 4);
    d.clear();
    for (const auto& x : still.points) d.push_back(q.normal.dot(x - q.centroid));
    const SupervoxelChange s = change_of(q, d, sigma_T, 1.96);
    EXPECT_FALSE(s.significant()) << s.change << " " << s.lod;
    EXPECT_NEAR(s.lod, lod, 0.2 * lod);
}

TEST(SupervoxelChange, TooFewPointsAreRefused) {
    const std::vector<Eigen::Vector3d> two = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()};
    EXPECT_THROW(patch_of(two, Eigen::Vector3d::UnitZ()), Error);
    const SupervoxelPatch q = patch_of(noisy_plane(0.001, 0, 5).points, Eigen::Vector3d::Zero());
    const std::vector<double> one = {0.001};
    EXPECT_THROW(change_of(q, one, 0.0, 1.96), Error);
}

}  // namespace
}  // namespace tlsmon::registration
