// Registration on planes and the congruence test (algorithms/registration/plane_fit.hpp,
// plane_registration.hpp) on the synthetic site of tests/support/synthetic_planes.hpp: twelve
// planar patches seen from a drifting station. The known answers: the drift, and which plane
// moved.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "algorithms/registration/plane_fit.hpp"
#include "algorithms/registration/plane_matching.hpp"
#include "algorithms/registration/plane_registration.hpp"
#include "core/error.hpp"
#include "tests/support/synthetic_planes.hpp"

namespace tlsmon::registration {
namespace {

using namespace test::synthetic_planes;

// The error of the estimated transformation against the truth: small rotation θ and
// translation, and their σ from the adjustment.
void expect_within(const RigidTransform& T, const Eigen::Affine3d& truth, double k, int& components,
                   int& covered) {
    const Eigen::AngleAxisd d(T.rotation * truth.rotation().transpose());
    const Eigen::Vector3d theta = d.angle() * d.axis();
    const Eigen::Vector3d dt = T.translation - truth.translation();
    const Eigen::Matrix<double, 6, 1> err = (Eigen::Matrix<double, 6, 1>() << theta, dt).finished();
    for (int i = 0; i < 6; ++i) {
        const double sigma = std::sqrt(T.small_rotation_covariance(i, i));
        ++components;
        covered += std::fabs(err(i)) <= k * sigma;
    }
}

TEST(PlaneFit, TheNormalsPredictedScatterIsItsActualScatter) {
    // 300 fits of one plane: the tilt's empirical variance towards each in-plane axis equals
    // the predicted σ²/λ_k, and the centroid's offset along the normal σ²/N.
    const SitePlane s{Eigen::Vector3d(0.1, -1.0, 0.2).normalized(), {5, 30, 4}};
    std::mt19937 rng(11);
    const Eigen::Affine3d I = Eigen::Affine3d::Identity();
    double tilt_sq = 0, predicted = 0, offset_sq = 0, predicted_offset = 0, scatter = 0;
    const int n = 300;
    for (int k = 0; k < n; ++k) {
        const FittedPlane f = fit_plane(sample(s, I, I, rng), kSigma);
        const Eigen::Vector3d nn =
            f.normal.dot(s.normal) < 0 ? Eigen::Vector3d(-f.normal) : f.normal;
        tilt_sq += (nn - s.normal).squaredNorm();
        predicted += f.normal_covariance.trace();
        offset_sq += std::pow(s.normal.dot(f.centroid - s.centre), 2);
        predicted_offset += f.centroid_variance;
        scatter += f.residual_sigma;
    }
    std::printf("tilt variance actual / predicted %.3f, centroid offset %.3f\n",
                tilt_sq / predicted, offset_sq / predicted_offset);
    EXPECT_NEAR(tilt_sq / predicted, 1.0, 0.2);
    EXPECT_NEAR(offset_sq / predicted_offset, 1.0, 0.25);
    // The points' own scatter along the normal is the noise's σ.
    EXPECT_NEAR(scatter / n, kSigma, 0.05 * kSigma);
}

TEST(PlaneFit, PointsOnALineAreRefused) {
    std::vector<Eigen::Vector3d> line;
    for (int i = 0; i < 10; ++i) line.emplace_back(i, 2.0 * i, 0.5 * i);
    EXPECT_THROW(fit_plane(line), Error);
    EXPECT_THROW(fit_plane(std::vector<Eigen::Vector3d>(2, Eigen::Vector3d::Zero())), Error);
}

TEST(PlaneRegistration, RecoversTheStationDriftWithAnHonestSigma) {
    // 100 epochs: the drift within 2σ for at least 90 % of the components, and the variance
    // factor near 1 on average (the planes' covariances are right).
    std::mt19937 rng(2026);
    int components = 0, covered = 0;
    double s0sq = 0;
    const int epochs = 100;
    for (int k = 0; k < epochs; ++k) {
        const Epoch e = epoch(rng);
        const PlaneAdjustment a = adjust_planes(e.planes, {}, RigidTransform{});
        EXPECT_EQ(a.transform.redundancy, 3 * 12 - 6);
        expect_within(a.transform, e.truth, 2.0, components, covered);
        s0sq += a.transform.variance_factor;
        // At the pier's top (10, 45, 40): within 1 mm of the truth.
        const Eigen::Vector3d top(10, 45, 40);
        EXPECT_LT((a.transform.apply(e.truth.inverse() * top) - top).norm(), 0.001);
    }
    EXPECT_GE(double(covered) / components, 0.90) << covered << " of " << components;
    EXPECT_NEAR(s0sq / epochs, 1.0, 0.15);
}

TEST(PlaneRegistration, TooFewPlanesOrParallelNormalsAreRefused) {
    std::mt19937 rng(5);
    const Epoch e = epoch(rng);
    std::vector<bool> two(e.planes.size(), false);
    two[2] = two[3] = true;
    EXPECT_THROW(adjust_planes(e.planes, two, RigidTransform{}), Error);
    // Three parallel walls: no translation along them, no rotation about their normal.
    std::vector<PlaneCorrespondence> parallel = {e.planes[2], e.planes[5], e.planes[2]};
    parallel[2].reference.centroid += Eigen::Vector3d(5, 0, 3);
    parallel[2].epoch.centroid += Eigen::Vector3d(5, 0, 3);
    EXPECT_THROW(adjust_planes(parallel, {}, RigidTransform{}), Error);
}

TEST(PlaneMatching, EachEpochPlaneFindsItsReferencePlaneFromTheStationsLastPose) {
    // The epoch's planes shuffled, the retaining wall (7) not seen, and three planes the
    // reference does not have: one parallel to the pier's south face 0.3 m in front of it, a
    // wall far from everything, a copy of the ground 10 m higher. With the identity as the
    // approximate transformation (the drift moves points by up to 30 mm at 100 m) every
    // seen plane finds its own, and nothing else is matched.
    std::mt19937 rng(31);
    const Epoch e = epoch(rng);
    const auto site = site_planes();
    std::vector<FittedPlane> reference, seen;
    std::vector<std::size_t> truth;  // seen[k] is reference[truth[k]], or SIZE_MAX
    for (std::size_t i = 0; i < e.planes.size(); ++i) {
        reference.push_back(e.planes[i].reference);
        if (i == 7) continue;
        seen.push_back(e.planes[i].epoch);
        truth.push_back(i);
    }
    const Eigen::Affine3d I = Eigen::Affine3d::Identity();
    for (const SitePlane& extra :
         {SitePlane{site[2].normal, site[2].centre - 0.3 * site[2].normal},
          SitePlane{Eigen::Vector3d(0.6, 0.8, 0), {-70, -40, 3}},
          SitePlane{site[0].normal, site[0].centre + Eigen::Vector3d(0, 0, 10)}}) {
        seen.push_back(fit_plane(sample(extra, I, e.truth.inverse(), rng), kSigma));
        truth.push_back(SIZE_MAX);
    }
    std::vector<std::size_t> order(seen.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<FittedPlane> shuffled;
    for (const auto k : order) shuffled.push_back(seen[k]);

    const auto matches = match_planes(reference, shuffled, RigidTransform{});
    ASSERT_EQ(matches.size(), 11u);
    for (const PlaneMatch& m : matches) EXPECT_EQ(truth[order[m.epoch]], m.reference);
}

TEST(Congruence, WithNothingMovedAPlaneIsFlaggedInAboutAlphaOfTheEpochs) {
    // α = 5 %: over 300 epochs the rate of epochs with a flagged plane lies within the
    // binomial 3σ band around α.
    const CongruenceParams params;  // α = 0.05
    std::mt19937 rng(77);
    const int epochs = 300;
    int flagged = 0;
    for (int k = 0; k < epochs; ++k)
        flagged += !congruence_test(epoch(rng).planes, {}).moved.empty();
    const double rate = double(flagged) / epochs;
    const double band = 3.0 * std::sqrt(params.alpha * (1 - params.alpha) / epochs);
    EXPECT_NEAR(rate, params.alpha, band) << flagged << " of " << epochs;
}

TEST(Congruence, AFoundationBlockMoved3MmAndTilted20ArcsecIsFoundAndTheDatumHolds) {
    // The block's south face (index 5) moves 3 mm south and tilts 20″ about the east axis
    // through its centre: found in ≥ 95 % of 200 epochs, first, and the transformation on
    // the remaining planes stays within 2σ of the truth for ≥ 90 % of the components.
    const auto site = site_planes();
    const Eigen::Vector3d c = site[5].centre;
    const Eigen::Affine3d motion = Eigen::Translation3d(0, -0.003, 0) * Eigen::Translation3d(c) *
                                   Eigen::AngleAxisd(20 * kArcsec, Eigen::Vector3d::UnitX()) *
                                   Eigen::Translation3d(-c);
    std::mt19937 rng(4242);
    const int epochs = 200;
    int found = 0, components = 0, covered = 0;
    double shift = 0, tilt = 0;  // sums over the epochs where it was found
    for (int k = 0; k < epochs; ++k) {
        const Epoch e = epoch(rng, 5, motion);
        const CongruenceResult r = congruence_test(e.planes, {});
        if (!r.moved.empty() && r.moved.front() == 5) {
            ++found;
            const PlaneMisclosure& m = r.adjustment.planes[5];
            EXPECT_FALSE(m.in_adjustment);
            shift += m.shift();
            // The mapped normal's tilt off the reference's, here towards +z: the 20″ rotation
            // about +x turns (0, −1, 0) into (0, −cos 20″, −sin 20″). One 3 × 3 m patch of
            // 400 points knows its normal to ≈ 24″ per axis, so the mean over the epochs is
            // compared, not each epoch's.
            const Eigen::Vector3d mapped =
                r.adjustment.transform.rotation * e.planes[5].epoch.normal;
            tilt += (mapped - e.planes[5].reference.normal).z();
            // Its change is significant on its own: T beyond χ²(3, 99.9 %).
            EXPECT_GT(m.test_statistic, chi_square_quantile(0.999, 3));
        }
        expect_within(r.adjustment.transform, e.truth, 2.0, components, covered);
    }
    EXPECT_GE(found, 190) << found << " of " << epochs;
    // The reported change: 3 mm along the face's normal (0, −1, 0), i.e. +3 mm, and 20″
    // (within 3σ of the mean: 34″ per epoch for the pair of fits, /√found).
    EXPECT_NEAR(shift / found, 0.003, 0.0003);
    EXPECT_NEAR(tilt / found / kArcsec, -20.0, 3.0 * 34.0 / std::sqrt(double(found)));
    EXPECT_GE(double(covered) / components, 0.90) << covered << " of " << components;
}

}  // namespace
}  // namespace tlsmon::registration
