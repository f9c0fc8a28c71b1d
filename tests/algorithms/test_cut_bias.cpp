// The bias of a segment's own cut (algorithms/campaign/cut_bias.hpp) against known answers:
// the share of points next to another label on a regular grid; a face whose noise lies along
// oblique pulses, cut by its measured height, is biased along its normal by (L/A)·u_n·u_b·σ²
// as derived, and the bound from the measured share covers it; the bound's added variance
// reaches the translations and nothing else.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <random>
#include <vector>

#include "algorithms/campaign/cut_bias.hpp"
#include "algorithms/campaign/segment_registration.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {
namespace {

TEST(CutBias, TheShareNextToAnotherLabelOnAGridIsTheBandOverTheWidth) {
    // 2 × 1 m at 0.01 m, label 0 left of x = 1, label 1 right of it; within 0.105 m of the
    // other label: the ten columns next to the line, 10 % of each. A third label alone far
    // away has only true edges: 0.
    std::vector<Eigen::Vector3d> points;
    std::vector<std::int32_t> label;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 100; ++j) {
            points.emplace_back(0.005 + 0.01 * i, 0.005 + 0.01 * j, 0.0);
            label.push_back(i < 100 ? 0 : 1);
        }
    for (int i = 0; i < 50; ++i) {
        points.emplace_back(10.0 + 0.01 * i, 0.0, 0.0);
        label.push_back(2);
    }
    const auto f = cut_fractions(points, label, 4, 0.105, 100000, 2);
    ASSERT_EQ(f.size(), 4u);
    EXPECT_DOUBLE_EQ(f[0], 0.10);
    EXPECT_DOUBLE_EQ(f[1], 0.10);
    EXPECT_DOUBLE_EQ(f[2], 0.0);
    EXPECT_TRUE(std::isnan(f[3]));  // no points
    // Every 10th point of label 0 probed: still the band's share.
    EXPECT_NEAR(cut_fractions(points, label, 2, 0.105, 1000, 1)[0], 0.10, 0.01);
    EXPECT_THROW(cut_fractions(points, std::vector<std::int32_t>(3, 0), 1, 0.1, 10), Error);
}

TEST(CutBias, AFaceCutByItsMeasuredHeightIsBiasedAsDerivedAndTheBoundCoversIt) {
    // The vertical face x = 0, 4 m long and 1 m high, 2 M points; the noise N(0, 20 mm) lies
    // along pulses from above and outside, u = (−1, 0, −1)/√2. The points measured above
    // z = 0.5 are the segment (a ground filter's cut): L = 4 m, A = 2 m², u_n·u_b = ½, so
    // their mean x is off by (L/A)·u_n·u_b·σ² = 2 · ½ · 0.0004 = +0.4 mm.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.020);
    const Eigen::Vector3d pulse = Eigen::Vector3d(-1, 0, -1).normalized();
    std::vector<Eigen::Vector3d> points(2000000);
    std::vector<std::int32_t> label(points.size());
    double sum_x = 0;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        points[i] = Eigen::Vector3d(0.0, 4 * u(rng), u(rng)) + noise(rng) * pulse;
        label[i] = points[i].z() > 0.5 ? 0 : -1;
        if (label[i] == 0) sum_x += points[i].x(), ++kept;
    }
    const double bias = sum_x / double(kept);
    const double standard_error = 0.020 * std::sqrt(0.5) / std::sqrt(double(kept));
    EXPECT_NEAR(bias, 0.0004, 4 * standard_error + 0.00002);

    const double f = cut_fractions(points, label, 1, 0.10, 20000, 2)[0];
    EXPECT_NEAR(f, 0.10 / 0.5, 0.03);  // the band over the segment's height
    const double sigma_n = 0.020 * std::sqrt(0.5);
    const double bound = cut_bias_bound(f, 0.10, 0.020, sigma_n);
    EXPECT_GE(bound, 0.9 * bias);  // at 45° the bound is the bias itself
    EXPECT_LE(bound, 1.3 * bias);
    // Seen square (all the noise along the normal) or along the face: no bias to bound.
    EXPECT_EQ(cut_bias_bound(f, 0.10, 0.020, 0.020), 0.0);
    EXPECT_EQ(cut_bias_bound(f, 0.10, 0.020, 0.0), 0.0);
    EXPECT_EQ(cut_bias_bound(0.0, 0.10, 0.020, sigma_n), 0.0);
}

TEST(CutBias, TheAddedVarianceReachesTheTranslationsOnly) {
    SegmentTransform t;
    t.outcome = SegmentOutcome::registered;
    t.radius = 2.0;
    Matrix6 D = Matrix6::Identity();
    D.diagonal().head<3>().setConstant(t.radius);
    t.observed = D;  // every direction observed, U = I
    t.observed_covariance = 1e-6 * Eigen::MatrixXd::Identity(6, 6);
    const Matrix6 Dinv = D.inverse();
    t.covariance = Dinv * t.observed_covariance * Dinv;
    const Matrix6 before = t.covariance;
    t.add_translation_variance(4e-6);
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(t.covariance(k, k), before(k, k));
    for (int k = 3; k < 6; ++k) EXPECT_NEAR(t.covariance(k, k), before(k, k) + 4e-6, 1e-15);
    EXPECT_NEAR(t.observed_covariance(3, 3), 5e-6, 1e-15);
    EXPECT_NEAR(t.observed_covariance(0, 0), 1e-6, 1e-15);
    // Not registered: nothing to add to.
    SegmentTransform none;
    none.add_translation_variance(1.0);
    EXPECT_EQ(none.covariance, Matrix6::Zero());
}

}  // namespace
}  // namespace tlsmon::campaign
