// Known answers for the weighted rigid transformation: exact recovery of a known drift from
// noise-free centres (with and without scale, near and far from identity), the redundancy
// numbers summing to the redundancy, and — over 200 seeded epochs with noisy centres — the
// actual error of each parameter and of a point on the pier 150 m away lying within the 2σ
// the adjustment predicts in ≥ 90 % of them, with RMS(error/σ) near 1.
#include <gtest/gtest.h>

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
