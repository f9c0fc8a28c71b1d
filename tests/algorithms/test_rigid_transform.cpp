// Known answers for the weighted rigid transformation: exact recovery of a known drift from
// noise-free centres (with and without scale, near and far from identity), the redundancy
// numbers summing to the redundancy, and — over 200 seeded epochs with noisy centres — the
// actual error of each parameter and of a point on the pier 150 m away lying within the 2σ
// the adjustment predicts in ≥ 90 % of them, with RMS(error/σ) near 1.
#include <gtest/gtest.h>

#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "algorithms/registration/registration_error.hpp"
#include "algorithms/registration/rigid_transform.hpp"
#include "core/error.hpp"
#include "tests/algorithms/registration_scenario.hpp"

namespace tlsmon::registration::test {
namespace {

TEST(RigidTransform, EulerAnglesRoundTrip) {
    const Eigen::Matrix3d R = rotation_from_euler(0.1, -0.2, 2.5);
    const Eigen::Vector3d e = euler_from_rotation(R);
    EXPECT_NEAR(e(0), 0.1, 1e-14);
    EXPECT_NEAR(e(1), -0.2, 1e-14);
    EXPECT_NEAR(e(2), 2.5, 1e-14);
    // R_z(κ)·R_y(φ)·R_x(ω) by hand for a quarter turn in κ: x -> y.
    EXPECT_TRUE(rotation_from_euler(0, 0, M_PI / 2)
                    .isApprox((Eigen::Matrix3d() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished(), 1e-15));
}

TEST(RigidTransform, RecoversAKnownDriftExactlyFromNoiseFreeCentres) {
    std::mt19937_64 rng(3);
    const TrueTransform truth = drift(rng);
    const auto centres = observe(target_centres(5), truth, rng, 0.0);
    const RigidTransform T = estimate_rigid_transform(centres, {});
    EXPECT_NEAR(T.omega, truth.omega, 1e-12);
    EXPECT_NEAR(T.phi, truth.phi, 1e-12);
    EXPECT_NEAR(T.kappa, truth.kappa, 1e-12);
    EXPECT_LT((T.translation - truth.translation).norm(), 1e-10);
    EXPECT_DOUBLE_EQ(T.scale, 1.0);
    EXPECT_LT(T.omega_sq, 1e-12);
    EXPECT_EQ(T.redundancy, 9);
    EXPECT_TRUE(T.quaternion.toRotationMatrix().isApprox(truth.rotation, 1e-12));
    // The 4×4 matrix maps an epoch point into the reference frame.
    const Eigen::Vector3d x(100, -40, 12);
    const Eigen::Vector4d h = T.matrix() * x.homogeneous();
    EXPECT_LT((h.head<3>() - (truth.rotation * x + truth.translation)).norm(), 1e-9);
}

TEST(RigidTransform, RecoversALargeRotationAndAScale) {
    // A scanner set up again on another heading: κ = 100°, φ = 3°; the range scale 25 ppm.
    std::mt19937_64 rng(5);
    TrueTransform truth = drift(rng, 100.0 * M_PI / 180.0);
    truth.phi = 3.0 * M_PI / 180.0;
    truth.rotation = rotation_from_euler(truth.omega, truth.phi, truth.kappa);
    const double s = 1.0 + 25e-6;
    std::vector<CentreObservation> centres;
    for (const auto& X : target_centres(5)) {
        CentreObservation c;
        c.reference = X;
        c.epoch = truth.rotation.transpose() * (X - truth.translation) / s;
        c.reference_covariance = c.epoch_covariance = centre_covariance(X);
        centres.push_back(c);
    }
    RigidTransformParams p;
    p.estimate_scale = true;
    const RigidTransform T = estimate_rigid_transform(centres, p);
    EXPECT_NEAR(T.kappa, truth.kappa, 1e-12);
    EXPECT_NEAR(T.phi, truth.phi, 1e-12);
    EXPECT_NEAR(T.omega, truth.omega, 1e-12);
    EXPECT_NEAR(T.scale, s, 1e-12);
    EXPECT_LT((T.translation - truth.translation).norm(), 1e-10);
    EXPECT_EQ(T.redundancy, 8);
    EXPECT_GT(T.covariance(6, 6), 0.0);
    // Closed form alone is exact on exact data (Umeyama 1991).
    const RigidTransform C = closed_form_transform(centres, true);
    EXPECT_NEAR(C.kappa, truth.kappa, 1e-10);
    EXPECT_NEAR(C.scale, s, 1e-10);
}

TEST(RigidTransform, RedundancyNumbersSumToTheRedundancy) {
    std::mt19937_64 rng(7);
    const auto centres = observe(target_centres(6), drift(rng), rng);
    const RigidTransform T = estimate_rigid_transform(centres, {});
    double sum = 0.0;
    for (const auto& r : T.residuals) {
        sum += r.redundancy_share;
        EXPECT_GT(r.redundancy_share, 0.0);
        EXPECT_LT(r.redundancy_share, 3.0);
    }
    EXPECT_EQ(T.redundancy, 12);
    EXPECT_NEAR(sum, 12.0, 1e-9);
}

TEST(RigidTransform, RefusesTooFewOrCollinearCentres) {
    std::mt19937_64 rng(9);
    const auto two = observe(target_centres(2), drift(rng), rng);
    EXPECT_THROW(estimate_rigid_transform(two, {}), Error);
    std::vector<Eigen::Vector3d> line{{10, 0, 0}, {20, 0, 0}, {30, 0, 0}, {40, 0, 0}};
    const auto collinear = observe(line, drift(rng), rng, 0.0);
    EXPECT_THROW(estimate_rigid_transform(collinear, {}), Error);
}

// 200 seeded epochs: error/σ of ω, φ, κ, tx, ty, tz and of the three coordinates of a pier
// point 150 m away.
void expect_honest(double base_kappa, CovarianceScaling scaling, const char* what) {
    constexpr int trials = 200;
    const auto truth_centres = target_centres(5);
    const Eigen::Vector3d pier(120.0, 90.0, 15.0);  // 150 m from the scanner, 16 m up
    const char* names[9] = {"omega", "phi",    "kappa",  "tx",    "ty",
                            "tz",    "pier x", "pier y", "pier z"};
    int within[9] = {};
    double sum2[9] = {};
    double sigma_pier = 0.0;
    RigidTransformParams p;
    p.scaling = scaling;
    std::mt19937_64 rng(2026);
    for (int t = 0; t < trials; ++t) {
        const TrueTransform truth = drift(rng, base_kappa);
        const auto centres = observe(truth_centres, truth, rng);
        const RigidTransform T = estimate_rigid_transform(centres, p);
        double err[9], sig[9];
        err[0] = T.omega - truth.omega;
        err[1] = T.phi - truth.phi;
        err[2] = T.kappa - truth.kappa;
        for (int k = 0; k < 3; ++k) err[3 + k] = T.translation(k) - truth.translation(k);
        for (int k = 0; k < 6; ++k) sig[k] = std::sqrt(T.covariance(k, k));
        const Eigen::Vector3d x = truth.rotation.transpose() * (pier - truth.translation);
        const Eigen::Vector3d e = T.apply(x) - pier;
        const Eigen::Matrix3d S = registration_covariance_at(T, x);
        for (int k = 0; k < 3; ++k) {
            err[6 + k] = e(k);
            sig[6 + k] = std::sqrt(S(k, k));
        }
        sigma_pier += std::sqrt(S.trace()) / trials;
        for (int k = 0; k < 9; ++k) {
            within[k] += std::fabs(err[k]) <= 2.0 * sig[k];
            sum2[k] += (err[k] / sig[k]) * (err[k] / sig[k]);
        }
    }
    for (int k = 0; k < 9; ++k) {
        const double share = static_cast<double>(within[k]) / trials;
        const double rms = std::sqrt(sum2[k] / trials);
        std::printf("%s %-7s within 2 sigma %.3f, RMS(error/sigma) %.3f\n", what, names[k], share,
                    rms);
        EXPECT_GE(share, 0.90) << what << " " << names[k];
        EXPECT_GT(rms, 0.8) << what << " " << names[k];
        EXPECT_LT(rms, 1.25) << what << " " << names[k];
    }
    std::printf("%s mean 3-D sigma at the pier point: %.2f mm\n", what, 1000.0 * sigma_pier);
}

TEST(RigidTransform, SigmaIsHonestForADaysDrift) {
    expect_honest(0.0, CovarianceScaling::larger_of, "drift");
}

TEST(RigidTransform, SigmaIsHonestWithTheAPrioriCovariances) {
    expect_honest(0.0, CovarianceScaling::a_priori, "a priori");
}

TEST(RigidTransform, SigmaIsHonestForAScannerSetUpOnAnotherHeading) {
    expect_honest(100.0 * M_PI / 180.0, CovarianceScaling::larger_of, "heading 100 deg");
}

// When is scaling the covariance by s0² honest? When the centres' stochastic model is right
// up to one common factor: s0² estimates that factor, and σ0²·Q_xx is right on average. But s0²
// is itself an estimate with r degrees of freedom (s0²·r/σ² ~ χ²(r)), so (x̂ − x)/σ̂ follows
// Student's t(r), not the normal distribution: ±1.96·s0·σ covers less than 95 % (92 % at
// r = 9, 5 targets). The stored σ carries the t expansion (covariance_factor), so its ±1.96 σ
// covers 95 %. 4000 epochs whose centres scatter twice their stated σ; the shares within each
// interval, with their binomial 99.9 % band (±3.3 σ).
TEST(RigidTransform, ScalingByS0SquaredNeedsTheTQuantileOfItsRedundancy) {
    constexpr int trials = 4000;
    const auto truth_centres = target_centres(5);
    struct Shares {
        double unscaled = 0, s0_only = 0, stored = 0, stored_68 = 0;
    } got;
    for (const auto scaling : {CovarianceScaling::a_priori, CovarianceScaling::a_posteriori}) {
        RigidTransformParams p;
        p.scaling = scaling;
        std::mt19937_64 rng(77);
        int within = 0, within_s0 = 0, within_68 = 0;
        for (int t = 0; t < trials; ++t) {
            const TrueTransform truth = drift(rng);
            const auto centres = observe(truth_centres, truth, rng, 2.0);
            const RigidTransform T = estimate_rigid_transform(centres, p);
            ASSERT_EQ(T.redundancy, 9);
            const double e = std::fabs(T.translation.x() - truth.translation.x());
            const double sigma = std::sqrt(T.covariance(3, 3));
            within += e <= 1.96 * sigma;
            within_68 += e <= sigma;
            within_s0 += e <= 1.96 * sigma / std::sqrt(t_expansion(9));
        }
        if (scaling == CovarianceScaling::a_priori) {
            got.unscaled = double(within) / trials;
        } else {
            got.stored = double(within) / trials;
            got.stored_68 = double(within_68) / trials;
            got.s0_only = double(within_s0) / trials;
        }
    }
    const auto band = [&](double p) { return 3.3 * std::sqrt(p * (1 - p) / trials); };
    const boost::math::students_t t9(9.0);
    // P(|Z| ≤ 1.96/2), P(|t9| ≤ 1.96), 0.95 and P(|t9| ≤ 1.96/t(0.975, 9)).
    const double p_unscaled = std::erf(0.98 / std::sqrt(2.0));
    const double p_s0 = 2 * boost::math::cdf(t9, 1.96) - 1;
    const double p_68 = 2 * boost::math::cdf(t9, std::sqrt(t_expansion(9))) - 1;
    std::printf(
        "tx within 1.96 sigma: a priori %.3f (expected %.3f), s0 alone %.3f (%.3f), "
        "stored %.3f (0.950); within 1 sigma stored %.3f (%.3f)\n",
        got.unscaled, p_unscaled, got.s0_only, p_s0, got.stored, got.stored_68, p_68);
    EXPECT_NEAR(got.unscaled, p_unscaled, band(p_unscaled));
    EXPECT_NEAR(got.s0_only, p_s0, band(p_s0));
    EXPECT_NEAR(got.stored, 0.95, band(0.95));
    EXPECT_NEAR(got.stored_68, p_68, band(p_68));
    EXPECT_LT(got.s0_only, 0.95 - band(0.95));  // the shortfall is real, not sampling
    // The expansion itself: t(0.975, 9) = 2.2622 (tables), 1 without redundancy.
    EXPECT_NEAR(std::sqrt(t_expansion(9)) * 1.959964, 2.2622, 1e-4);
    EXPECT_DOUBLE_EQ(t_expansion(0), 1.0);
}

TEST(RegistrationError, ZoneSummaryIsTheWorstOfItsPoints) {
    std::mt19937_64 rng(11);
    const auto centres = observe(target_centres(5), drift(rng), rng);
    const RigidTransform T = estimate_rigid_transform(centres, {});
    const std::vector<Eigen::Vector3d> zone{{50, 40, 2}, {120, 90, 15}, {80, 60, 30}};
    const std::vector<Eigen::Vector3d> normals{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const ZoneRegistrationError z = zone_registration_error(T, zone, normals);
    double worst = 0.0, worst_normal = 0.0;
    for (std::size_t i = 0; i < zone.size(); ++i) {
        const Eigen::Matrix3d S = registration_covariance_at(T, zone[i]);
        worst = std::max(worst, std::sqrt(S.trace()));
        worst_normal = std::max(worst_normal, registration_sigma_along(T, zone[i], normals[i]));
        EXPECT_NEAR(registration_sigma_along(T, zone[i], normals[i]),
                    std::sqrt(S(static_cast<int>(i), static_cast<int>(i))), 1e-15);
    }
    EXPECT_DOUBLE_EQ(z.max_sigma_3d, worst);
    EXPECT_DOUBLE_EQ(z.max_sigma_normal, worst_normal);
    // Farther from the targets' centroid, larger: the rotation's error grows with the lever arm.
    EXPECT_GT(std::sqrt(registration_covariance_at(T, zone[1]).trace()),
              std::sqrt(registration_covariance_at(T, zone[0]).trace()));
    EXPECT_THROW(zone_registration_error(T, zone, std::vector<Eigen::Vector3d>(2)), Error);
}

}  // namespace
}  // namespace tlsmon::registration::test
