// Known answers for the sphere-target fit: a 72.5 mm sphere ~30 m from a scanner, sampled as
// a TLS samples it (rays on a regular angular grid of 0.013°, range noise along the ray, only
// the scanner-facing cap visible), with and without a mast, a ground surface and mixed
// pixels behind the silhouette; the fitted centre against the true one, and its σ against
// the actual error over many seeded scans.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "algorithms/registration/sphere_fit.hpp"

namespace tlsmon::registration {
namespace {

constexpr double kRadius = 0.0725;
constexpr double kStep = 0.013 * M_PI / 180.0;  // the `pier` preset's angular step

struct SyntheticTarget {
    Eigen::Vector3d centre{24.0, 15.0, 0.6};  // 28.3 m from the scanner at the origin
    double radius = kRadius;
    double range_sigma = 0.0005;     // m, along the ray
    bool mast = false;               // a pole from the sphere down, up into it
    double mast_radius = 0.015;      // m
    double ground_below = 0.0;       // > 0: a horizontal surface this far below the centre
    double mixed_pixel_share = 0.0;  // share of silhouette rays that return a mixed range
    double window = 0.20;            // m, points kept within this distance of the prediction
    bool occlude_left_half = false;  // a post in front hides the left half of the target
};

// Ray/sphere, ray/vertical cylinder and ray/plane hits from the origin along unit d.
double hit_sphere(const Eigen::Vector3d& d, const Eigen::Vector3d& c, double r) {
    const double b = d.dot(c);
    const double disc = b * b - (c.squaredNorm() - r * r);
    return disc < 0 ? -1.0 : b - std::sqrt(disc);
}

double hit_mast(const Eigen::Vector3d& d, const Eigen::Vector3d& c, double r_mast, double z_top) {
    const Eigen::Vector2d dh = d.head<2>(), ch = c.head<2>();
    const double a = dh.squaredNorm(), b = dh.dot(ch), cc = ch.squaredNorm() - r_mast * r_mast;
    const double disc = b * b - a * cc;
    if (disc < 0) return -1.0;
    const double t = (b - std::sqrt(disc)) / a;
    return (d.z() * t <= z_top) ? t : -1.0;
}

// The points within `window` of the centre; `sphere_points` counts those on the sphere.
std::vector<Eigen::Vector3d> scan_target(const SyntheticTarget& s, std::uint64_t seed,
                                         std::size_t* sphere_points = nullptr) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, s.range_sigma);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Eigen::Vector3d& c = s.centre;
    const double dist = c.norm();
    const double az0 = std::atan2(c.y(), c.x()), el0 = std::asin(c.z() / dist);
    const double half = std::asin(std::min(1.0, s.window / dist));
    // Where the grid falls on the target changes from scan to scan.
    const double jaz = unit(rng) * kStep, jel = unit(rng) * kStep;
    std::vector<Eigen::Vector3d> pts;
    for (double el = el0 - half + jel; el <= el0 + half; el += kStep)
        for (double az = az0 - half / std::cos(el0) + jaz; az <= az0 + half / std::cos(el0);
             az += kStep) {
            const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                    std::sin(el));
            double t = hit_sphere(d, c, s.radius);
            bool on_sphere = t > 0;
            const double miss =
                (c - d * d.dot(c)).norm() - s.radius;  // ray's distance past the silhouette
            if (s.mixed_pixel_share > 0 && std::fabs(miss) < 0.003 &&
                unit(rng) < s.mixed_pixel_share) {
                // Footprint half on the sphere, half on whatever is behind: a range in between.
                t = d.dot(c) + 0.02 + 0.5 * unit(rng);
                on_sphere = false;
            } else if (t < 0 && s.mast) {
                // The pole enters the sphere where its surface meets the sphere's.
                t = hit_mast(
                    d, c, s.mast_radius,
                    c.z() - std::sqrt(s.radius * s.radius - s.mast_radius * s.mast_radius));
            }
            if (s.ground_below > 0 && d.z() < 0) {
                const double tg = (c.z() - s.ground_below) / d.z();
                if (tg > 0 && (t < 0 || tg < t)) {
                    t = tg;
                    on_sphere = false;
                }
            }
            if (t <= 0) continue;
            const Eigen::Vector3d p = d * (t + noise(rng));
            if (s.occlude_left_half &&
                (p - c).dot(Eigen::Vector3d::UnitZ().cross(c).normalized()) < 0)
                continue;
            if ((p - c).norm() > s.window) continue;
            pts.push_back(p);
            if (on_sphere && sphere_points) ++*sphere_points;
        }
    return pts;
}

SphereFitParams params_for(double radius = kRadius) {
    SphereFitParams p;
    p.radius = radius;
    return p;
}

// Held from below, its cap about the mount left out (the stage's default).
SphereFitParams mounted_below(double radius = kRadius) {
    SphereFitParams p = params_for(radius);
    p.mount = -Eigen::Vector3d::UnitZ();
    p.mount_cap_deg = 30.0;
    return p;
}

TEST(SphereFit, ScannerFacingCapGivesTheTrueCentre) {
    SyntheticTarget s;
    const auto pts = scan_target(s, 1);
    ASSERT_GT(pts.size(), 150u);
    const Eigen::Vector3d predicted = s.centre + Eigen::Vector3d(0.02, -0.015, 0.01);
    const SphereFit fit = fit_sphere(pts, predicted, params_for());
    ASSERT_TRUE(fit.found()) << describe(fit.reason) << ": " << fit.detail;
    const Eigen::Vector3d e = fit.centre - s.centre;
    EXPECT_LT(e.norm(), 0.0005);
    for (int k = 0; k < 3; ++k)
        EXPECT_LT(std::fabs(e(k)), 4.0 * std::sqrt(fit.centre_covariance(k, k)));
    EXPECT_GE(fit.inliers + 3, pts.size());  // a clean scan: at most a few beyond 4σ̂
    EXPECT_NEAR(fit.free_radius, kRadius, 0.001);
    EXPECT_LT(std::fabs(fit.radius_deviation), 4.0 * fit.free_radius_sigma);
    // Range noise seen along the normal: σ0 between 0.5·σ_r and σ_r.
    EXPECT_GT(fit.sigma0, 0.00025);
    EXPECT_LT(fit.sigma0, 0.00055);
    // A TLS sees at most a hemisphere: coverage up to 1/3, well above the bound.
    EXPECT_GT(fit.coverage, 0.1);
    EXPECT_LT(fit.coverage, 0.34);
}

TEST(SphereFit, SameSeedSameResult) {
    SyntheticTarget s;
    s.mast = true;
    const auto pts = scan_target(s, 5);
    const SphereFit a = fit_sphere(pts, s.centre, params_for());
    const SphereFit b = fit_sphere(pts, s.centre, params_for());
    ASSERT_TRUE(a.found());
    EXPECT_EQ(a.centre, b.centre);
    EXPECT_EQ(a.inliers, b.inliers);
}

// Over 200 seeded scans the error of each centre coordinate lies within 2σ in ≥ 90 % of
// them, and the RMS of error/σ is near 1 (a padded σ would give far less, an optimistic one
// far more).
void expect_honest_sigma(SyntheticTarget s, int trials, const char* what,
                         const SphereFitParams& params) {
    int within[3] = {0, 0, 0};
    double sum_ratio2[3] = {0, 0, 0};
    double sum_classic2[3] = {0, 0, 0};
    int found = 0;
    for (int t = 0; t < trials; ++t) {
        const auto pts = scan_target(s, 1000 + static_cast<std::uint64_t>(t));
        const SphereFit fit = fit_sphere(pts, s.centre, params);
        if (!fit.found()) continue;
        ++found;
        for (int k = 0; k < 3; ++k) {
            const double ratio =
                (fit.centre(k) - s.centre(k)) / std::sqrt(fit.centre_covariance(k, k));
            within[k] += std::fabs(ratio) <= 2.0;
            sum_ratio2[k] += ratio * ratio;
            const double classic = (fit.centre(k) - s.centre(k)) /
                                   std::sqrt(fit.centre_covariance_homoscedastic(k, k));
            sum_classic2[k] += classic * classic;
        }
    }
    ASSERT_EQ(found, trials) << what;
    for (int k = 0; k < 3; ++k) {
        const double share = static_cast<double>(within[k]) / trials;
        const double rms = std::sqrt(sum_ratio2[k] / trials);
        EXPECT_GE(share, 0.90) << what << " coordinate " << k;
        EXPECT_GT(rms, 0.8) << what << " coordinate " << k;
        EXPECT_LT(rms, 1.25) << what << " coordinate " << k;
        std::printf(
            "%s coordinate %d: within 2 sigma %.3f, RMS(error/sigma) %.3f (s0^2 N^-1: %.3f)\n",
            what, k, share, rms, std::sqrt(sum_classic2[k] / trials));
    }
}

TEST(SphereFit, SigmaIsHonestOnCleanScans) {
    expect_honest_sigma(SyntheticTarget{}, 200, "clean", params_for());
}

TEST(SphereFit, SigmaIsHonestWithMastGroundAndMixedPixels) {
    SyntheticTarget s;
    s.mast = true;
    s.ground_below = 0.15;
    s.mixed_pixel_share = 0.6;
    expect_honest_sigma(s, 200, "outliers", params_for());
}

TEST(SphereFit, SigmaIsHonestWithHalfTheCapOccluded) {
    SyntheticTarget s;
    s.occlude_left_half = true;
    expect_honest_sigma(s, 200, "half", params_for());
}

TEST(SphereFit, SigmaIsHonestWithTheMountsCapLeftOut) {
    SyntheticTarget s;
    s.mast = true;
    s.mast_radius = 0.025;
    expect_honest_sigma(s, 200, "mount's cap left out", mounted_below());
}

// Seen from 5° below its centre the scan holds the sphere's lowest part: the points within 30°
// of its lowest point are left out, and only they; held from above, those about its top.
TEST(SphereFit, TheMountsCapIsLeftOut) {
    SyntheticTarget s;
    s.centre.z() = 2.5;
    s.mast = true;
    s.mast_radius = 0.025;
    const auto pts = scan_target(s, 11);
    const auto in_cap = [&](const Eigen::Vector3d& mount) {
        std::size_t n = 0;
        for (const auto& p : pts) {
            const Eigen::Vector3d d = p - s.centre;
            n += std::fabs(d.norm() - s.radius) < 0.002 &&
                 d.dot(mount) > std::cos(30.0 * M_PI / 180.0) * d.norm();
        }
        return double(n);
    };
    const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
    ASSERT_GE(in_cap(down), 10);  // the ring between the pole (20°) and 30°
    const SphereFit all = fit_sphere(pts, s.centre, params_for());
    const SphereFit below = fit_sphere(pts, s.centre, mounted_below());
    SphereFitParams held_above = mounted_below();
    held_above.mount = -down;
    const SphereFit above = fit_sphere(pts, s.centre, held_above);
    ASSERT_TRUE(all.found() && below.found() && above.found());
    // ±3: the fitted centres are not the true one, and the σ̂ bound moves a point or two.
    EXPECT_NEAR(double(all.inliers - below.inliers), in_cap(down), 3.0);
    EXPECT_NEAR(double(all.inliers - above.inliers), in_cap(-down), 3.0);
    EXPECT_LT((below.centre - s.centre).norm(), 0.0005);
}

TEST(SphereFit, MastGroundAndMixedPixelsAreRejected) {
    SyntheticTarget s;
    s.mast = true;
    s.ground_below = 0.15;
    s.mixed_pixel_share = 0.6;
    std::size_t on_sphere = 0;
    const auto pts = scan_target(s, 7, &on_sphere);
    ASSERT_GT(pts.size(), on_sphere + 40);  // points that are not the sphere
    const SphereFit fit = fit_sphere(pts, s.centre + Eigen::Vector3d(0, 0, -0.03), params_for());
    ASSERT_TRUE(fit.found()) << describe(fit.reason) << ": " << fit.detail;
    EXPECT_LT((fit.centre - s.centre).norm(), 0.0006);
    EXPECT_LT(fit.inliers, on_sphere + 5);
    EXPECT_GT(fit.inliers, on_sphere * 8 / 10);
    EXPECT_NEAR(fit.free_radius, kRadius, 0.001);
}

TEST(SphereFit, HalfOccludedCapIsFoundWithALargerSigma) {
    SyntheticTarget s;
    auto pts = scan_target(s, 11);
    const SphereFit full = fit_sphere(pts, s.centre, params_for());
    // A post in front hides the left half of the target as the scanner sees it.
    const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(s.centre).normalized();
    std::erase_if(pts, [&](const Eigen::Vector3d& p) { return (p - s.centre).dot(side) < 0.0; });
    const SphereFit half = fit_sphere(pts, s.centre, params_for());
    ASSERT_TRUE(half.found()) << describe(half.reason) << ": " << half.detail;
    const Eigen::Vector3d e = half.centre - s.centre;
    for (int k = 0; k < 3; ++k)
        EXPECT_LT(std::fabs(e(k)), 4.0 * std::sqrt(half.centre_covariance(k, k)));
    EXPECT_GT(half.centre_covariance.trace(), 1.5 * full.centre_covariance.trace());
    EXPECT_LT(half.coverage, full.coverage);
}

TEST(SphereFit, SliverOfTheSphereIsABadFit) {
    SyntheticTarget s;
    auto pts = scan_target(s, 13);
    // Only a 14° cap facing the scanner (the rest hidden behind a plate with a hole): all
    // normals nearly parallel, the centre poorly fixed across the line of sight.
    const Eigen::Vector3d towards = -s.centre.normalized();
    std::erase_if(pts, [&](const Eigen::Vector3d& p) {
        return (p - s.centre).normalized().dot(towards) < std::cos(14.0 * M_PI / 180.0);
    });
    SphereFitParams p = params_for();
    p.min_points = 10;
    ASSERT_GE(pts.size(), 10u);
    const SphereFit fit = fit_sphere(pts, s.centre, p);
    EXPECT_EQ(fit.status, SphereFitStatus::bad_fit);
    EXPECT_EQ(fit.reason, SphereFitReason::coverage_one_sided) << fit.detail;
    EXPECT_LT(fit.coverage, 0.02);
}

TEST(SphereFit, WrongRadiusFailsTheFreeRadiusCheck) {
    SyntheticTarget s;
    s.radius = kRadius + 0.006;  // a 78.5 mm sphere configured as 72.5 mm
    const auto pts = scan_target(s, 17);
    const SphereFit fit = fit_sphere(pts, s.centre, params_for(kRadius));
    EXPECT_EQ(fit.status, SphereFitStatus::bad_fit) << describe(fit.reason) << ": " << fit.detail;
    EXPECT_EQ(fit.reason, SphereFitReason::radius_check_failed);
    EXPECT_NEAR(fit.radius_deviation, 0.006, 0.0015);
}

TEST(SphereFit, NoisyPointsFailTheRmsBound) {
    SyntheticTarget s;
    s.range_sigma = 0.002;
    const auto pts = scan_target(s, 19);
    SphereFitParams p = params_for();
    p.max_rms = 0.001;
    p.max_radius_deviation = 0.01;
    const SphereFit fit = fit_sphere(pts, s.centre, p);
    EXPECT_EQ(fit.status, SphereFitStatus::bad_fit);
    EXPECT_EQ(fit.reason, SphereFitReason::residual_rms_too_large) << fit.detail;
    EXPECT_GT(fit.rms, 0.001);
}

TEST(SphereFit, TooFewPointsOrNoSphereIsNotFound) {
    SyntheticTarget s;
    const auto pts = scan_target(s, 23);
    const std::vector<Eigen::Vector3d> few(pts.begin(), pts.begin() + 12);
    const SphereFit a = fit_sphere(few, s.centre, params_for());
    EXPECT_EQ(a.status, SphereFitStatus::not_found);
    EXPECT_EQ(a.reason, SphereFitReason::too_few_points);

    // A wall 0.15 m behind the predicted centre and nothing else (the target is gone).
    std::vector<Eigen::Vector3d> wall;
    const Eigen::Vector3d n = s.centre.normalized();
    const Eigen::Vector3d e1 = Eigen::Vector3d::UnitZ().cross(n).normalized(), e2 = n.cross(e1);
    for (int i = -25; i <= 25; ++i)
        for (int j = -25; j <= 25; ++j)
            wall.push_back(s.centre + 0.15 * n + 0.006 * (i * e1 + j * e2));
    const SphereFit b = fit_sphere(wall, s.centre, params_for());
    EXPECT_EQ(b.status, SphereFitStatus::not_found);
    EXPECT_EQ(b.reason, SphereFitReason::no_consensus) << b.detail;
}

}  // namespace
}  // namespace tlsmon::registration
