// The personal laser scanner's campaign (simulator/pls.hpp) against known answers: the walk's
// length and positions, the three drift models, the measured points against the surface
// points their pulses hit, and a render that does not depend on the thread count.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/error.hpp"
#include "simulator/pls.hpp"
#include "simulator/ray_cast.hpp"

namespace tlsmon::sim {
namespace {

PlsCampaign small_campaign(SlamDriftModel model, double sigma) {
    PlsCampaign c;
    c.trajectory = walk_around_pier(preset_small());
    c.scanner.pulse_rate = 2000;
    c.scanner.range_sigma = sigma;
    c.drift.model = model;
    return c;
}

TEST(Pls, WalksTheLoopAroundThePierAtItsPace) {
    const Site site = preset_small();
    const PlsTrajectory walk = walk_around_pier(site);
    ASSERT_EQ(walk.waypoints.size(), 5u);
    // 8 m west, 4 m east, 6 m south and north of the 15 × 7 m pier: 27 × 19 m, 92 m round.
    EXPECT_NEAR(walk_duration(walk), 92.0, 1e-9);
    EXPECT_TRUE(sensor_position(walk, 0).isApprox(Eigen::Vector3d(-6, 39, 1.5)));
    EXPECT_TRUE(sensor_position(walk, 13.5).isApprox(Eigen::Vector3d(7.5, 39, 1.5)));
    EXPECT_TRUE(sensor_position(walk, 27 + 19).isApprox(Eigen::Vector3d(21, 58, 1.5)));
    EXPECT_TRUE(sensor_position(walk, 1e6).isApprox(walk.waypoints.back()));
}

TEST(Pls, LinearDriftGrowsInProportionToTheTimeWalked) {
    SlamDrift d;
    d.model = SlamDriftModel::linear;
    const SlamDriftPath path(d, 100.0);
    EXPECT_TRUE(path.at(0).translation.isZero());
    EXPECT_TRUE(path.at(50).translation.isApprox(0.5 * d.end_translation));
    EXPECT_TRUE(path.at(100).rotation.isApprox(1e-3 * d.end_rotation_mrad));
    // About the sensor: a point 10 m ahead along x turned by ω_z moves by 10·ω_z along y.
    SlamPoseError e;
    e.rotation = Eigen::Vector3d(0, 0, 1e-3);
    const Eigen::Vector3d s(1, 2, 3);
    const Eigen::Vector3d moved = e.apply(s, s + Eigen::Vector3d(10, 0, 0));
    EXPECT_NEAR(moved.y() - s.y(), 10 * std::sin(1e-3), 1e-12);
    SlamDrift none;
    EXPECT_TRUE(SlamDriftPath(none, 100).at(42).translation.isZero());
}

TEST(Pls, RandomWalkDriftHasItsSpectralDensityAndItsSeed) {
    SlamDrift d;
    d.model = SlamDriftModel::random_walk;
    const double duration = 20000;
    const SlamDriftPath path(d, duration);
    EXPECT_TRUE(path.at(0).translation.isZero());
    // Increments over one knot: σ = density·√knot per axis.
    double sum2 = 0;
    int n = 0;
    for (double t = 0; t + 1 <= duration; t += 1, ++n)
        sum2 += (path.at(t + 1).translation - path.at(t).translation).squaredNorm() / 3;
    EXPECT_NEAR(std::sqrt(sum2 / n), d.translation_density, 0.05 * d.translation_density);
    // Continuous between knots, reproducible, and another seed walks elsewhere.
    const auto mid = path.at(10.5).translation, a = path.at(10).translation,
               b = path.at(11).translation;
    EXPECT_TRUE(mid.isApprox(0.5 * (a + b)));
    EXPECT_TRUE(
        SlamDriftPath(d, duration).at(1234.5).translation.isApprox(path.at(1234.5).translation));
    d.seed += 1;
    EXPECT_FALSE(
        SlamDriftPath(d, duration).at(1234.5).translation.isApprox(path.at(1234.5).translation));
    EXPECT_EQ(drift_model("random-walk"), SlamDriftModel::random_walk);
    EXPECT_THROW(drift_model("spiral"), Error);
}

TEST(Pls, MeasuresTheSurfaceAlongEachPulseWithItsRangeNoise) {
    const Site site = preset_small();
    const PlsCampaign c = small_campaign(SlamDriftModel::none, 0.02);
    const PlsCloud cloud = render_pls(site, 0, c, 2);
    ASSERT_GT(cloud.points.size(), 50000u);
    ASSERT_EQ(cloud.truth.size(), cloud.points.size());
    ASSERT_EQ(cloud.surface.size(), cloud.points.size());
    double sum2 = 0, across = 0;
    std::size_t pier = 0, ground = 0;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const Eigen::Vector3d s = sensor_position(c.trajectory, cloud.time[i]);
        const Eigen::Vector3d ray = (cloud.truth[i] - s).normalized();
        const Eigen::Vector3d e = cloud.points[i] - cloud.truth[i];
        sum2 += e.squaredNorm();
        across = std::max(across, (e - e.dot(ray) * ray).norm());
        const double range = (cloud.truth[i] - s).norm();
        EXPECT_LE(range, c.scanner.max_range + 1e-9);
        pier += Surface(cloud.surface[i]) == Surface::pier;
        ground += Surface(cloud.surface[i]) == Surface::ground;
    }
    // Range noise only, and along the ray (to the 5 µs of the time stored as a float, which
    // moves the sensor by 5 µm at walking pace).
    EXPECT_NEAR(std::sqrt(sum2 / double(cloud.points.size())), 0.02, 0.001);
    EXPECT_LT(across, 1e-6);
    EXPECT_GT(pier, 5000u);
    EXPECT_GT(ground, 5000u);
    // The times run along the walk.
    EXPECT_LT(cloud.time.front(), 1.0f);
    EXPECT_GT(cloud.time.back(), float(cloud.duration - 1.0));
}

TEST(Pls, DriftMovesEachPointByThePoseErrorAtItsTime) {
    const Site site = preset_small();
    const PlsCampaign c = small_campaign(SlamDriftModel::linear, 0.0);
    const PlsCloud cloud = render_pls(site, 0, c, 2);
    const SlamDriftPath path(c.drift, cloud.duration);
    double worst = 0;
    for (std::size_t i = 0; i < cloud.points.size(); i += 97) {
        const Eigen::Vector3d s = sensor_position(c.trajectory, cloud.time[i]);
        // The time is stored as a float: 2e-6 s off at 90 s, far below the drift's change.
        const Eigen::Vector3d expected = path.at(cloud.time[i]).apply(s, cloud.truth[i]);
        worst = std::max(worst, (cloud.points[i] - expected).norm());
    }
    EXPECT_LT(worst, 1e-6);
    EXPECT_GT((cloud.points.back() - cloud.truth.back()).norm(), 0.01);
}

TEST(Pls, DoesNotDependOnTheThreadCount) {
    const Site site = preset_small();
    const PlsCampaign c = small_campaign(SlamDriftModel::random_walk, 0.02);
    const PlsCloud one = render_pls(site, 0, c, 1), two = render_pls(site, 0, c, 2);
    ASSERT_EQ(one.points.size(), two.points.size());
    for (std::size_t i = 0; i < one.points.size(); i += 101)
        EXPECT_EQ(one.points[i], two.points[i]);
}

TEST(Pls, RefusesACampaignThatCannotBeWalked) {
    PlsCampaign c = small_campaign(SlamDriftModel::none, 0.02);
    c.trajectory.speed = 0;
    EXPECT_THROW(validate(c), Error);
    c = small_campaign(SlamDriftModel::none, 0.02);
    c.trajectory.waypoints.resize(1);
    EXPECT_THROW(validate(c), Error);
    c = small_campaign(SlamDriftModel::none, 0.02);
    c.scanner.max_range = 0.1;
    EXPECT_THROW(validate(c), Error);
}

}  // namespace
}  // namespace tlsmon::sim
