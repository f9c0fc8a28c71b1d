// Patch-based M3C2's kernel (algorithms/patches/) against known answers: the Gauss–Markov
// plane of exact points is that plane; its σ̂ and its height's σ at a point off the centroid
// agree with the scatter of many noisy draws; two planes a known distance apart give that
// distance along the patch normal at the reference centroid even when the epoch's points
// cover only part of the footprint of a sloping patch; the LoD95 covers the true distance at
// its nominal rate over independent draws; stray points leave the plane before it is fitted;
// points go to the patch whose footprint and depth
// hold them (the nearer along the normal when two do), and the moments do not depend on the
// number of threads.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "algorithms/patches/patch_distance.hpp"
#include "algorithms/patches/patch_index.hpp"
#include "algorithms/patches/patch_plane.hpp"
#include "core/error.hpp"

namespace tlsmon::patches {
namespace {

// A frame about (10, 20, 1) with the normal (0.6, −0.8, 0) turned 10° upwards.
PatchFrame frame() {
    const Eigen::Vector3d n =
        Eigen::Vector3d(0.6 * std::cos(0.1745), -0.8 * std::cos(0.1745), std::sin(0.1745));
    return PatchFrame::about({10, 20, 1}, n);
}

// Points of the plane w = a + b·u + c·v of `f`'s frame over [u0, u1] × [−0.5, 0.5] every 5 cm,
// with N(0, σ) along the normal.
std::vector<Eigen::Vector3d> plane_points(const PatchFrame& f, double a, double b, double c,
                                          double sigma, std::mt19937& rng, double u0 = -0.5,
                                          double u1 = 0.5) {
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<Eigen::Vector3d> out;
    for (double u = u0 + 0.025; u < u1; u += 0.05) {
        for (double v = -0.475; v < 0.5; v += 0.05) {
            const double w = a + b * u + c * v + (sigma > 0 ? noise(rng) : 0.0);
            out.push_back(f.origin + u * f.u + v * f.v + w * f.normal);
        }
    }
    return out;
}

PlaneMoments moments_of(const PatchFrame& f, const std::vector<Eigen::Vector3d>& points) {
    PlaneMoments m;
    for (const auto& p : points) m.add(f.local(p));
    return m;
}

TEST(PatchPlane, TheFrameIsRightHandedAndOrthonormal) {
    const PatchFrame f = frame();
    EXPECT_NEAR(f.normal.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.u.dot(f.normal), 0.0, 1e-12);
    EXPECT_NEAR(f.v.dot(f.u), 0.0, 1e-12);
    EXPECT_NEAR(f.u.cross(f.v).dot(f.normal), 1.0, 1e-12);
    EXPECT_TRUE(f.local(f.origin + 0.3 * f.u - 0.2 * f.v + 0.01 * f.normal)
                    .isApprox(Eigen::Vector3d(0.3, -0.2, 0.01), 1e-12));
}

TEST(PatchPlane, ExactPointsGiveBackTheirPlane) {
    std::mt19937 rng(1);
    const PatchFrame f = frame();
    const PlaneFit fit = fit_plane(moments_of(f, plane_points(f, 0.004, 0.01, -0.02, 0, rng)));
    ASSERT_TRUE(fit.valid);
    EXPECT_EQ(fit.count, 400u);
    EXPECT_NEAR(fit.slope.x(), 0.01, 1e-12);
    EXPECT_NEAR(fit.slope.y(), -0.02, 1e-12);
    EXPECT_NEAR(fit.height_at({0.3, 0.2}), 0.004 + 0.003 - 0.004, 1e-12);
    EXPECT_NEAR(fit.sigma, 0.0, 1e-9);
}

TEST(PatchPlane, PointsOnALineLeaveTheFitInvalid) {
    PlaneMoments m;
    for (int i = 0; i < 50; ++i) m.add({0.02 * i, 0.01 * i, 0.001 * (i % 3)});
    EXPECT_FALSE(fit_plane(m).valid);
    PlaneMoments three;
    for (int i = 0; i < 3; ++i) three.add({double(i), double(i * i), 0});
    EXPECT_FALSE(fit_plane(three).valid);  // fewer than 4 points
}

// σ̂ and σ_h at a point off the centroid against the scatter of 2000 draws.
TEST(PatchPlane, TheHeightsSigmaMatchesTheScatterOfDraws) {
    std::mt19937 rng(2);
    const PatchFrame f = frame();
    const Eigen::Vector2d at(0.4, -0.3);
    double sum = 0, sum2 = 0, sigma_hat = 0, predicted = 0;
    const int draws = 2000;
    for (int k = 0; k < draws; ++k) {
        const PlaneFit fit = fit_plane(moments_of(f, plane_points(f, 0.0, 0.01, 0.0, 0.002, rng)));
        const double h = fit.height_at(at) - (0.01 * 0.4);
        sum += h, sum2 += h * h;
        sigma_hat += fit.sigma / draws;
        predicted += fit.height_sigma_at(at) / draws;
    }
    const double scatter = std::sqrt(sum2 / draws - (sum / draws) * (sum / draws));
    EXPECT_NEAR(sigma_hat, 0.002, 0.00005);
    EXPECT_NEAR(sum / draws, 0.0, 3 * scatter / std::sqrt(double(draws)));
    // The standard error of a standard deviation from 2000 draws is about 1.6 %.
    EXPECT_NEAR(predicted / scatter, 1.0, 0.05);
    // By hand: σ²(1/m + gᵀS⁻¹g) with S of the 20 × 20 grid (Σu² = 20·Σ over one row).
    double s_row = 0;
    for (double u = -0.475; u < 0.5; u += 0.05) s_row += u * u;
    const double s = 20 * s_row;
    EXPECT_NEAR(predicted, 0.002 * std::sqrt(1.0 / 400 + (0.16 + 0.09) / s), 0.00002);
}

TEST(PatchDistance, TwoPlanesAKnownDistanceApartOnPartOfTheFootprint) {
    std::mt19937 rng(3);
    const PatchFrame f = frame();
    const Parameters p;
    // A sloping patch; the epoch moved 5 mm along the normal and covers only u > 0: a mean
    // of raw heights there would read 5 mm + the slope's 0.05 × 0.25 m = 17.5 mm.
    const PlaneFit reference =
        fit_plane(moments_of(f, plane_points(f, 0.0, 0.05, 0.0, 0.0005, rng)));
    const PlaneFit epoch =
        fit_plane(moments_of(f, plane_points(f, 0.005, 0.05, 0.0, 0.0005, rng, 0.0, 0.5)));
    const PatchResult r = patch_distance(reference, epoch, 0.0003, p);
    ASSERT_EQ(r.outcome, PatchOutcome::measured);
    EXPECT_NEAR(r.distance.distance, 0.005, 4 * r.distance.sampling_sigma);
    EXPECT_TRUE(r.distance.significant);
    // σ_d² = σ₁²/m₁ + σ_h₂² + σ_T².
    const double s1 = reference.sigma / std::sqrt(400.0);
    const double s2 = epoch.height_sigma_at(reference.centroid);
    EXPECT_NEAR(r.distance.sigma, std::sqrt(s1 * s1 + s2 * s2 + 0.0003 * 0.0003), 1e-12);
    EXPECT_NEAR(r.distance.lod, 1.96 * r.distance.sigma, 1e-15);
}

TEST(PatchDistance, TheLodCoversTheTrueDistanceAtItsNominalRate) {
    std::mt19937 rng(4);
    std::normal_distribution<double> registration(0.0, 0.0002);
    const PatchFrame f = frame();
    const Parameters p;
    int within = 0;
    const int draws = 2000;
    for (int k = 0; k < draws; ++k) {
        // The registration's error: one offset of the whole epoch along the normal.
        const double e = registration(rng);
        const PlaneFit reference =
            fit_plane(moments_of(f, plane_points(f, 0.0, 0.02, -0.01, 0.002, rng)));
        const PlaneFit epoch = fit_plane(
            moments_of(f, plane_points(f, 0.003 + e, 0.02, -0.01, 0.002, rng, -0.5, 0.2)));
        const PatchResult r = patch_distance(reference, epoch, 0.0002, p);
        within += std::abs(r.distance.distance - 0.003) <= r.distance.lod;
    }
    // Binomial: 95 % of 2000 ± 3 standard deviations (0.49 %).
    EXPECT_NEAR(double(within) / draws, 0.95, 0.015);
}

TEST(PatchDistance, RoughOrSparsePatchesGiveNoDistance) {
    std::mt19937 rng(5);
    const PatchFrame f = frame();
    Parameters p;
    const PlaneFit smooth = fit_plane(moments_of(f, plane_points(f, 0, 0, 0, 0.001, rng)));
    const PlaneFit rough = fit_plane(moments_of(f, plane_points(f, 0, 0, 0, 0.02, rng)));
    EXPECT_EQ(patch_distance(rough, smooth, 0, p).outcome, PatchOutcome::rough);
    EXPECT_TRUE(std::isnan(patch_distance(rough, smooth, 0, p).distance.distance));
    // Smooth points on a plane at 17° to the patch's own are not the surface it stands for;
    // at 8° they still give a distance.
    const PlaneFit tilted = fit_plane(moments_of(f, plane_points(f, 0, 0.3, 0, 0.001, rng)));
    EXPECT_EQ(patch_distance(tilted, smooth, 0, p).outcome, PatchOutcome::rough);
    const PlaneFit leaning = fit_plane(moments_of(f, plane_points(f, 0, 0, 0.14, 0.001, rng)));
    EXPECT_EQ(patch_distance(leaning, smooth, 0, p).outcome, PatchOutcome::measured);
    p.min_points = 500;
    EXPECT_EQ(patch_distance(smooth, smooth, 0, p).outcome, PatchOutcome::few_reference_points);
    p.min_points = 30;
    PlaneMoments few;
    for (int i = 0; i < 10; ++i) few.add({0.1 * i, 0.07 * (i % 4), 0});
    EXPECT_EQ(patch_distance(smooth, fit_plane(few), 0, p).outcome, PatchOutcome::few_epoch_points);
    p.search_depth = 0;
    EXPECT_THROW(validate(p), Error);
}

TEST(PatchPlane, StrayPointsLeaveThePlaneBeforeItIsFitted) {
    std::mt19937 rng(7);
    const PatchFrame f = frame();
    const auto clean = plane_points(f, 0.002, 0.01, 0.0, 0.0005, rng);
    std::vector<Eigen::Vector3f> uvw;
    for (const auto& p : clean) uvw.push_back(f.local(p).cast<float>());
    // 40 mixed returns strung 2 to 60 mm behind one corner of the patch.
    for (int i = 0; i < 40; ++i)
        uvw.emplace_back(-0.45f + 0.002f * float(i), -0.45f, -0.002f - 0.0015f * float(i));
    PlaneMoments all;
    for (const auto& p : uvw) all.add(p.cast<double>());
    const PlaneFit spoilt = fit_plane(all);
    const PlaneFit fit = fit_plane(inlier_moments(uvw));
    EXPECT_GT(spoilt.sigma, 0.005);  // what a least-squares fit of everything would say
    // The plane's 400 points and the 2 strays that lie within 1σ of it (at 2 and 3.5 mm).
    EXPECT_EQ(fit.count, 402u);
    EXPECT_NEAR(fit.sigma, 0.0005, 0.00005);
    EXPECT_NEAR(fit.height_at(fit.centroid), 0.002 + 0.01 * fit.centroid.x(), 0.0001);
    // Points of a plane alone: all stay.
    std::vector<Eigen::Vector3f> plane(uvw.begin(), uvw.begin() + 400);
    EXPECT_EQ(inlier_moments(plane).count(), 400u);
}

// Two unit squares of one plane side by side (footprints on 0.1 m cells), and a third one
// 5 cm behind the first, parallel.
std::vector<Patch> three_patches() {
    const PatchFrame f = PatchFrame::about({0, 0, 0}, Eigen::Vector3d::UnitZ());
    std::vector<Patch> out;
    for (const auto& [origin, du] : std::vector<std::pair<Eigen::Vector3d, double>>{
             {{0, 0, 0}, 0.0}, {{0, 0, 0}, 1.0}, {{0, 0, -0.05}, 0.0}}) {
        Patch p;
        p.frame = PatchFrame::about(origin, Eigen::Vector3d::UnitZ());
        std::vector<Eigen::Vector3d> samples;
        for (double u = 0.05; u < 1; u += 0.1)
            for (double v = 0.05; v < 1; v += 0.1)
                samples.push_back(origin + (u + du) * f.u + v * f.v);
        p.footprint = footprint_of(p.frame, samples, 0.1);
        out.push_back(std::move(p));
    }
    return out;
}

TEST(PatchIndex, APointGoesToThePatchWhoseFootprintAndDepthHoldIt) {
    const PatchIndex index(three_patches(), 0.10);
    const PatchFrame f = PatchFrame::about({0, 0, 0}, Eigen::Vector3d::UnitZ());
    EXPECT_EQ(index.patches()[0].footprint.cells(), 100u);
    const auto at = [&](double u, double v, double w) {
        Eigen::Vector3d uvw;
        return index.find(u * f.u + v * f.v + w * f.normal, uvw);
    };
    EXPECT_EQ(at(0.5, 0.5, 0.01), 0);   // nearer the first than the one behind
    EXPECT_EQ(at(0.5, 0.5, -0.04), 2);  // nearer the one behind
    EXPECT_EQ(at(1.5, 0.5, 0.09), 1);   // the second, within the depth
    EXPECT_EQ(at(1.5, 0.5, 0.11), -1);  // beyond the depth
    EXPECT_EQ(at(2.05, 0.5, 0.0), -1);  // beyond the footprints
    EXPECT_EQ(at(0.5, -0.05, 0.0), -1);
}

TEST(PatchIndex, ThePointsOnEachPatchDoNotDependOnTheThreads) {
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> uniform(-0.2, 2.2);
    std::normal_distribution<double> noise(0.0, 0.002);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 300000; ++i) points.emplace_back(uniform(rng), uniform(rng), noise(rng));
    const PatchIndex index(three_patches(), 0.10);
    const Eigen::Matrix3d A = Eigen::AngleAxisd(0.001, Eigen::Vector3d::UnitX()).matrix();
    const auto one = patch_points(index, points, A, Eigen::Vector3d(0, 0, 0.001), 1);
    const auto two = patch_points(index, points, A, Eigen::Vector3d(0, 0, 0.001), 2);
    ASSERT_EQ(one.size(), 3u);
    std::size_t total = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(one[k], two[k]);
        total += one[k].size();
    }
    // Inside [0, 2] × [0, 1]: 2 of the 2.4 × 2.4 square, all within the depth of one patch.
    EXPECT_NEAR(double(total) / 300000, 2.0 / (2.4 * 2.4), 0.01);
}

// Neighbours on one surface whose footprints share the cells 0.8 ≤ u < 1.0: the second's
// plane 0.3 mm off the first's (a tilt between patch frames). A point there goes to the
// patch whose footprint's centre is nearer, whatever its height: choosing the nearer plane
// would hand the points that the noise lifted to one patch and the rest to the other.
TEST(PatchIndex, OnOneSurfaceTheNoiseDoesNotChooseThePatch) {
    std::vector<Patch> two;
    for (const auto& [u0, u1, offset] :
         std::vector<std::tuple<double, double, double>>{{0.0, 1.0, 0.0}, {0.8, 1.8, 3e-4}}) {
        Patch p;
        p.frame = PatchFrame::about({0, 0, offset}, Eigen::Vector3d::UnitZ());
        std::vector<Eigen::Vector3d> samples;
        for (double u = u0 + 0.05; u < u1; u += 0.1)
            for (double v = 0.05; v < 1; v += 0.1) samples.emplace_back(u, v, offset);
        p.footprint = footprint_of(p.frame, samples, 0.1);
        two.push_back(std::move(p));
    }
    const PatchIndex index(two, 0.10);
    Eigen::Vector3d uvw;
    EXPECT_EQ(index.find({0.85, 0.5, 0.0002}, uvw), 0);   // nearer the first's centre (0.5)
    EXPECT_EQ(index.find({0.95, 0.5, -0.0002}, uvw), 1);  // nearer the second's (1.3)

    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.8), v(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.001);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 200000; ++i) points.emplace_back(u(rng), v(rng), noise(rng));
    const auto on =
        patch_points(index, points, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 1);
    for (std::size_t k = 0; k < 2; ++k) {
        double sum = 0;
        for (const auto& q : on[k]) sum += q.z();
        const double offset = k == 0 ? 0.0 : -3e-4;  // the points' height above this plane
        // Nearest along the normal instead: −0.09 mm and +0.09 mm.
        EXPECT_NEAR(sum / double(on[k].size()), offset, 4 * 0.001 / std::sqrt(on[k].size()))
            << "patch " << k << ", " << on[k].size() << " points";
    }
}

}  // namespace
}  // namespace tlsmon::patches
