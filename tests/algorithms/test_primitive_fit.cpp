// The primitives' kernel (algorithms/primitives/) against known answers: a cylinder, a plane
// and a sphere of exact points are recovered from a coarse start; with the scanner's noise
// the fitted parameters fall within their covariance at its nominal rate over independent
// draws (the covariance is honest, not only small); stray returns and the silhouette leave
// the fit; the registration's Jacobian matches a moved cylinder re-fitted; the change test's
// statistic, limit and LoD are the χ² ones.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/primitives/primitive_change.hpp"
#include "algorithms/primitives/primitive_fit.hpp"
#include "core/error.hpp"

namespace tlsmon::primitives {
namespace {

constexpr double kArcsec = std::numbers::pi / (180.0 * 3600.0);
const Eigen::Vector3d kScanner(0.0, 0.0, 1.5);

// The scanner's noise of the tests: 1 mm + 10 ppm in range, 3″ across.
ScannerNoise noise() {
    return ScannerNoise{};
}

// What a scanner at kScanner sees of a surface: the beams through a grid of directions
// (every `step` rad) met by `hit` (the range, or NaN), with N(0, σ_r) along the beam and
// N(0, ρ·σ_θ) across it.
template <class Hit>
std::vector<Eigen::Vector3d> scan(Hit hit, double az0, double az1, double el0, double el1,
                                  double step, std::mt19937* rng) {
    std::normal_distribution<double> n01(0.0, 1.0);
    const ScannerNoise sn = noise();
    std::vector<Eigen::Vector3d> out;
    for (double az = az0; az < az1; az += step) {
        for (double el = el0; el < el1; el += step) {
            const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                    std::sin(el));
            const double t = hit(d);
            if (!std::isfinite(t)) continue;
            Eigen::Vector3d p = kScanner + t * d;
            if (rng) {
                const Eigen::Vector3d e1 = d.cross(Eigen::Vector3d::UnitZ()).normalized();
                const Eigen::Vector3d e2 = d.cross(e1);
                const double across = t * sn.angular_sigma();
                p += d * sn.range_sigma(t) * n01(*rng) + e1 * across * n01(*rng) +
                     e2 * across * n01(*rng);
            }
            out.push_back(p);
        }
    }
    return out;
}

// A vertical-ish cylinder of radius r about the line c + s·a, 0 ≤ z ≤ h: the nearer root.
auto cylinder_hit(const Eigen::Vector3d& c, const Eigen::Vector3d& a, double r, double h) {
    return [=](const Eigen::Vector3d& d) {
        const Eigen::Vector3d w = kScanner - c;
        const Eigen::Vector3d dp = d - a * a.dot(d), wp = w - a * a.dot(w);
        const double A = dp.squaredNorm(), B = 2 * dp.dot(wp), C = wp.squaredNorm() - r * r;
        const double disc = B * B - 4 * A * C;
        if (disc < 0) return std::numeric_limits<double>::quiet_NaN();
        const double t = (-B - std::sqrt(disc)) / (2 * A);
        const double z = (kScanner + t * d).z();
        return t > 0 && z >= 0 && z <= h ? t : std::numeric_limits<double>::quiet_NaN();
    };
}

// The column of the tests: 4 m across, 20 m high, 47 m north of the scanner, leaning
// (30″, −15″).
struct Column {
    Eigen::Vector3d foot{0.0, 49.0, 0.0};
    Eigen::Vector3d axis = Eigen::Vector3d(30 * kArcsec, -15 * kArcsec, 1.0).normalized();
    double radius = 2.0;
};

std::vector<Eigen::Vector3d> column_points(const Column& col, double step, std::mt19937* rng) {
    const double pi = std::numbers::pi;
    return scan(cylinder_hit(col.foot, col.axis, col.radius, 20.0), 0.5 * pi - 0.05,
                0.5 * pi + 0.05, -0.04, 0.4, step, rng);
}

// The fitted lean of the axis (towards x, y), rad.
Eigen::Vector2d lean(const Primitive& p) {
    const Eigen::Vector3d a = p.direction();
    return {a.x() / a.z(), a.y() / a.z()};
}

TEST(PrimitiveFit, ExactCylinderFromACoarseStart) {
    const Column col;
    const auto points = column_points(col, 0.0004, nullptr);
    ASSERT_GT(points.size(), 20000u);
    // A start as RANSAC gives one: 1 cm off, leaning 0.05°, radius 2 cm too large.
    const Primitive start = cylinder_about(col.foot + Eigen::Vector3d(0.01, -0.01, 8.0),
                                           Eigen::Vector3d(0.0008, 0.0005, 1.0), col.radius + 0.02);
    const Fit fit = fit_primitive(points, kScanner, noise(), start, FitParameters{});
    ASSERT_EQ(fit.status, FitStatus::fitted) << to_string(fit.status);
    EXPECT_NEAR(fit.primitive.radius(), 2.0, 1e-7);
    const Eigen::Vector2d l = lean(fit.primitive);
    EXPECT_NEAR(l.x() / kArcsec, 30.0, 1e-3);
    EXPECT_NEAR(l.y() / kArcsec, -15.0, 1e-3);
    // The axis point lies on the true axis.
    const Eigen::Vector3d v = fit.primitive.point() - col.foot;
    EXPECT_LT((v - col.axis * col.axis.dot(v)).norm(), 1e-7);
    EXPECT_LT(fit.rms, 1e-7);
}

TEST(PrimitiveFit, ExactPlaneAndSphere) {
    const Eigen::Vector3d n = Eigen::Vector3d(0.2, -1.0, 0.1).normalized();
    const Eigen::Vector3d on(3.0, 30.0, 4.0);
    const auto plane = scan(
        [&](const Eigen::Vector3d& d) {
            const double t = n.dot(on - kScanner) / n.dot(d);
            return t > 0 ? t : std::numeric_limits<double>::quiet_NaN();
        },
        1.4, 1.6, 0.0, 0.2, 0.002, nullptr);
    const Fit pf = fit_primitive(
        plane, kScanner, noise(),
        plane_through(on + Eigen::Vector3d(0, 0.02, 0), n + Eigen::Vector3d(0.01, 0, 0)),
        FitParameters{});
    ASSERT_EQ(pf.status, FitStatus::fitted);
    EXPECT_NEAR(std::abs(pf.primitive.direction().dot(n)), 1.0, 1e-12);
    EXPECT_NEAR(n.dot(pf.primitive.point() - on), 0.0, 1e-9);

    const Eigen::Vector3d c(1.0, 12.0, 2.0);
    const auto sphere = scan(
        [&](const Eigen::Vector3d& d) {
            const Eigen::Vector3d oc = kScanner - c;
            const double b = d.dot(oc), disc = b * b - (oc.squaredNorm() - 0.25);
            return disc >= 0 ? -b - std::sqrt(disc) : std::numeric_limits<double>::quiet_NaN();
        },
        1.45, 1.7, -0.05, 0.15, 0.001, nullptr);
    FitParameters sp;
    sp.max_incidence_deg = 80;
    const Fit sf = fit_primitive(sphere, kScanner, noise(),
                                 sphere_at(c + Eigen::Vector3d(0.01, 0.01, -0.01), 0.51), sp);
    ASSERT_EQ(sf.status, FitStatus::fitted);
    EXPECT_NEAR((sf.primitive.point() - c).norm(), 0.0, 1e-8);
    EXPECT_NEAR(sf.primitive.radius(), 0.5, 1e-8);
}

// 200 independent noisy scans of the column: the fitted lean and radius fall within 1.96 σ
// of the truth at the nominal rate (the binomial band of 200 draws at 95 %: 184–196), and the
// covariance's σ agrees with the draws' scatter within 20 %.
TEST(PrimitiveFit, CovarianceCoversTheTruthAtItsNominalRate) {
    const Column col;
    std::mt19937 rng(7);
    const Primitive start =
        cylinder_about(col.foot + Eigen::Vector3d(0, 0, 8.0), Eigen::Vector3d::UnitZ(), col.radius);
    int within_lean = 0, within_radius = 0;
    std::vector<double> lean_x;
    double sigma_lean_x = 0;
    const int draws = 200;
    for (int k = 0; k < draws; ++k) {
        const auto points = column_points(col, 0.002, &rng);
        const Fit fit = fit_primitive(points, kScanner, noise(), start, FitParameters{});
        ASSERT_EQ(fit.status, FitStatus::fitted);
        // The lean in the frame's (b1, b2) = (x, y): parameters 2 and 3.
        const Eigen::Vector2d truth(col.axis.x() / col.axis.z(), col.axis.y() / col.axis.z());
        const Eigen::Vector2d e = fit.primitive.x.segment<2>(2) - truth;
        const Eigen::Matrix2d S = fit.covariance.block<2, 2>(2, 2);
        within_lean += e.dot(S.inverse() * e) <= 5.991;
        within_radius +=
            std::abs(fit.primitive.radius() - col.radius) <= 1.96 * std::sqrt(fit.covariance(4, 4));
        lean_x.push_back(e.x());
        sigma_lean_x += std::sqrt(S(0, 0)) / draws;
    }
    EXPECT_GE(within_lean, 184);
    EXPECT_LE(within_lean, 196);
    EXPECT_GE(within_radius, 184);
    EXPECT_LE(within_radius, 196);
    double mean = 0, sq = 0;
    for (double v : lean_x) mean += v / draws;
    for (double v : lean_x) sq += (v - mean) * (v - mean) / (draws - 1);
    EXPECT_NEAR(std::sqrt(sq) / sigma_lean_x, 1.0, 0.2);
}

TEST(PrimitiveFit, StrayReturnsAndTheSilhouetteStayOut) {
    const Column col;
    std::mt19937 rng(3);
    auto points = column_points(col, 0.001, &rng);
    const std::size_t clean = points.size();
    // 3 % stray returns 1–4 cm in front of the surface (rain, dust, mixed pixels).
    std::uniform_real_distribution<double> off(0.01, 0.04);
    for (std::size_t i = 0; i < clean; i += 33) {
        const Eigen::Vector3d d = (points[i] - kScanner).normalized();
        points.push_back(points[i] - off(rng) * d);
    }
    const Primitive start =
        cylinder_about(col.foot + Eigen::Vector3d(0, 0, 8.0), Eigen::Vector3d::UnitZ(), col.radius);
    const Fit fit = fit_primitive(points, kScanner, noise(), start, FitParameters{});
    ASSERT_EQ(fit.status, FitStatus::fitted);
    EXPECT_LT(fit.used, clean);  // the silhouette (beyond 75°) and the strays are not used
    EXPECT_NEAR(fit.primitive.radius(), 2.0, 4 * std::sqrt(fit.covariance(4, 4)));
    EXPECT_LT(fit.s0, 1.3);
}

TEST(PrimitiveFit, TooFewPointsIsSaid) {
    const Column col;
    const auto points = column_points(col, 0.02, nullptr);
    FitParameters p;
    p.min_points = 10000;
    const Fit fit = fit_primitive(points, kScanner, noise(),
                                  cylinder_about(col.foot, Eigen::Vector3d::UnitZ(), 2.0), p);
    EXPECT_EQ(fit.status, FitStatus::too_few_points);
}

// Moving the column's points by a small rotation about a centre, a translation and a scale,
// and fitting again, changes the parameters by J·(θ, t, s), to first order.
TEST(PrimitiveChange, MotionJacobianMatchesAMovedFit) {
    const Column col;
    const auto points = column_points(col, 0.001, nullptr);
    const Primitive start =
        cylinder_about(col.foot + Eigen::Vector3d(0, 0, 8.0), Eigen::Vector3d::UnitZ(), col.radius);
    const Fit before = fit_primitive(points, kScanner, noise(), start, FitParameters{});
    ASSERT_EQ(before.status, FitStatus::fitted);
    const Eigen::Vector3d centre(2.0, -1.0, 0.5), theta(20e-6, -35e-6, 50e-6),
        t(0.002, -0.001, 0.003);
    const double s = 30e-6;
    std::vector<Eigen::Vector3d> moved;
    for (const auto& p : points)
        moved.push_back(p + theta.cross(p - centre) + t + s * (p - centre));
    const Eigen::Vector3d scanner =
        kScanner + theta.cross(kScanner - centre) + t + s * (kScanner - centre);
    const Fit after = fit_primitive(moved, scanner, noise(), before.primitive, FitParameters{});
    ASSERT_EQ(after.status, FitStatus::fitted);
    Eigen::Matrix<double, 7, 1> m;
    m << theta, t, s;
    const Eigen::VectorXd predicted = motion_jacobian(before.primitive, centre) * m;
    const Eigen::VectorXd actual = after.primitive.x - before.primitive.x;
    // First order: the motion's square (θ²·50 m ≈ 1e-7 m) is what remains.
    for (int i = 0; i < 5; ++i)
        EXPECT_NEAR(actual[i], predicted[i], 1e-3 * std::abs(predicted[i]) + 1e-10) << i;
}

TEST(PrimitiveChange, TestIsTheChiSquareOne) {
    Eigen::VectorXd v(2);
    v << 3.0, 0.0;
    Eigen::MatrixXd S(2, 2);
    S << 1.0, 0.0, 0.0, 4.0;
    const VectorTest t = test_change(v, S, 0.05);
    EXPECT_NEAR(t.statistic, 9.0, 1e-12);
    EXPECT_NEAR(t.limit, 5.991464547, 1e-6);
    EXPECT_NEAR(t.lod, std::sqrt(5.991464547), 1e-6);
    EXPECT_TRUE(t.significant);
    v << 0.0, 3.0;  // along the less precise component: T = 9/4
    const VectorTest u = test_change(v, S, 0.05);
    EXPECT_NEAR(u.statistic, 2.25, 1e-12);
    EXPECT_NEAR(u.lod, 2.0 * std::sqrt(5.991464547), 1e-6);
    EXPECT_FALSE(u.significant);
    Eigen::VectorXd one(1);
    one << 0.1;
    EXPECT_NEAR(test_change(one, Eigen::MatrixXd::Constant(1, 1, 0.01), 0.05).lod, 1.959964 * 0.1,
                1e-6);
    EXPECT_THROW(test_change(v, Eigen::MatrixXd::Zero(2, 2), 0.05), Error);
}

}  // namespace
}  // namespace tlsmon::primitives
