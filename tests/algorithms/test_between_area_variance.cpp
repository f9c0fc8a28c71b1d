// The between-area variance component (algorithms/vectors/between_area_variance.hpp) against
// known answers: equal variances about a mean give the sample variance less the stated one;
// values drawn with a known τ about a quadratic field give τ back; values within their stated
// σ give τ² near 0; too few areas for the field give no estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "algorithms/vectors/between_area_variance.hpp"

namespace tlsmon::vectors {
namespace {

TEST(BetweenAreaVariance, EqualVariancesAboutAMeanGiveTheSampleVarianceLessTheStatedOne) {
    // y = 1, 2, 3, 4, 5: sample variance (n − 1 divisor) 2.5; stated variance 0.5 → τ² = 2.
    const Eigen::MatrixXd X = Eigen::MatrixXd::Ones(5, 1);
    const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(5, 1.0, 5.0);
    const auto r = between_area_variance(X, y, Eigen::VectorXd::Constant(5, 0.5));
    EXPECT_EQ(r.dof, 4);
    EXPECT_NEAR(r.q, 10.0 / 0.5, 1e-12);
    EXPECT_NEAR(r.tau2, 2.0, 1e-12);
    // Stated variances larger than the scatter: no between-area part.
    EXPECT_EQ(between_area_variance(X, y, Eigen::VectorXd::Constant(5, 4.0)).tau2, 0.0);
}

// Areas over a 10 m × 40 m face, σ_k from 0.05 to 0.8 mm, errors N(0, σ_k² + τ²) about a
// quadratic field of millimetres.
struct Draw {
    Eigen::MatrixX2d positions;
    Eigen::VectorXd values, variances;
};
Draw draw(double tau, unsigned seed, int n = 600) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::normal_distribution<double> N(0.0, 1.0);
    Draw d{Eigen::MatrixX2d(n, 2), Eigen::VectorXd(n), Eigen::VectorXd(n)};
    for (int k = 0; k < n; ++k) {
        const double h = 10.0 * U(rng), v = 40.0 * U(rng);
        const double sigma = 0.00005 + 0.00075 * U(rng);
        d.positions.row(k) << h, v;
        d.variances(k) = sigma * sigma;
        const double field = 0.001 + 0.0001 * h - 0.0002 * v + 5e-6 * v * v;
        d.values(k) = field + std::sqrt(sigma * sigma + tau * tau) * N(rng);
    }
    return d;
}

TEST(BetweenAreaVariance, AKnownTauAboutAQuadraticFieldIsFound) {
    const double tau = 0.0003;
    double mean = 0;
    const int draws = 20;
    for (int s = 0; s < draws; ++s) {
        const Draw d = draw(tau, 100 + unsigned(s));
        const Eigen::MatrixXd X = zone_field(d.positions);
        ASSERT_EQ(X.cols(), 6);
        const auto r = between_area_variance(X, d.values, d.variances);
        EXPECT_EQ(r.dof, 600 - 6);
        EXPECT_NEAR(std::sqrt(r.tau2), tau, 0.3 * tau) << "draw " << s;
        mean += std::sqrt(r.tau2) / draws;
    }
    EXPECT_NEAR(mean, tau, 0.05 * tau);  // unbiased to a few per cent over the draws
}

TEST(BetweenAreaVariance, HonestVariancesLeaveNoBetweenAreaPart) {
    for (int s = 0; s < 10; ++s) {
        const Draw d = draw(0.0, 200 + unsigned(s));
        const auto r = between_area_variance(zone_field(d.positions), d.values, d.variances);
        // τ̂'s own noise at τ = 0 (Q's spread, √(2(n − p)), over Σw): ≈ 0.07 mm when positive,
        // which in quadrature beside the median σ of 0.43 mm adds 3 %.
        EXPECT_LT(std::sqrt(r.tau2), 0.0001) << "draw " << s;
        EXPECT_NEAR(r.q / double(r.dof), 1.0, 0.2);
    }
}

TEST(BetweenAreaVariance, FewAreasFitAPlaneAndTooFewGiveNoEstimate) {
    const Draw d = draw(0.0003, 300, 10);
    const Eigen::MatrixXd plane = zone_field(d.positions);
    EXPECT_EQ(plane.cols(), 3);  // below kQuadraticAreas
    EXPECT_EQ(between_area_variance(plane, d.values, d.variances).dof, 7);
    const Eigen::MatrixXd four = zone_field(d.positions.topRows(4));
    const auto none = between_area_variance(four, d.values.head(4), d.variances.head(4));
    EXPECT_EQ(none.dof, 0);
    EXPECT_EQ(none.tau2, 0.0);
    // A variance of zero cannot weigh its area.
    Eigen::VectorXd zero = d.variances;
    zero(0) = 0.0;
    EXPECT_EQ(between_area_variance(plane, d.values, zero).dof, 0);
}

}  // namespace
}  // namespace tlsmon::vectors
