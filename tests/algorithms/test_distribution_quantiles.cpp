// Known answers for the critical values of the registration tests: table values of the
// standard normal and χ² quantiles (e.g. Abramowitz & Stegun 1964, tables 26.1 and 26.8).
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/registration/distribution_quantiles.hpp"
#include "core/error.hpp"

namespace tlsmon::registration {
namespace {

TEST(DistributionQuantiles, NormalQuantilesMatchTheTable) {
    EXPECT_NEAR(normal_quantile(0.975), 1.959964, 1e-6);
    EXPECT_NEAR(normal_quantile(0.9995), 3.290527, 1e-6);
    EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-12);
    EXPECT_NEAR(normal_quantile(0.025), -1.959964, 1e-6);
    EXPECT_NEAR(normal_quantile(1e-10), -6.361341, 1e-5);
}

TEST(DistributionQuantiles, ChiSquareQuantilesMatchTheTable) {
    EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841459, 1e-5);
    EXPECT_NEAR(chi_square_quantile(0.95, 3), 7.814728, 1e-5);
    EXPECT_NEAR(chi_square_quantile(0.999, 3), 16.26624, 1e-4);
    EXPECT_NEAR(chi_square_quantile(0.999, 1), 10.82757, 1e-4);
    EXPECT_NEAR(chi_square_quantile(0.95, 10), 18.30704, 1e-4);
    EXPECT_NEAR(chi_square_quantile(0.05, 10), 3.940299, 1e-5);
    EXPECT_NEAR(chi_square_quantile(0.95, 100), 124.3421, 1e-3);
}

TEST(DistributionQuantiles, ChiSquareDistributionFunctionAndTail) {
    // χ²(2) is exponential: F(x) = 1 − exp(−x/2).
    EXPECT_NEAR(chi_square_cdf(3.0, 2), 1.0 - std::exp(-1.5), 1e-13);
    EXPECT_NEAR(chi_square_upper_tail(200.0, 2) / std::exp(-100.0), 1.0, 1e-10);
    EXPECT_NEAR(chi_square_cdf(7.814728, 3), 0.95, 1e-7);
    EXPECT_THROW(chi_square_quantile(1.0, 3), Error);
    EXPECT_THROW(chi_square_quantile(0.5, 0), Error);
}

TEST(DistributionQuantiles, BaardasNoncentralityForOneDegreeOfFreedom) {
    // Baarda 1968: α0 = 0.1 %, β0 = 20 % gives δ0 = 4.13, λ0 = 17.07; for one degree of
    // freedom λ0 = (Φ⁻¹(1 − α/2) + Φ⁻¹(1 − β))² up to the far tail's share.
    EXPECT_NEAR(detectable_noncentrality(0.001, 0.8, 1), 17.07, 0.01);
    EXPECT_NEAR(std::sqrt(detectable_noncentrality(0.05, 0.8, 1)), 1.96 + 0.8416, 0.001);
    // With no noncentrality the distribution is the central one.
    EXPECT_NEAR(noncentral_chi_square_cdf(7.814728, 3, 0.0), 0.95, 1e-7);
    // For 2 degrees of freedom √X is Rice-distributed (ν = √λ, σ = 1): the integral of
    // r·exp(−(r² + ν²)/2)·I0(r·ν) over [0, √10] for λ = 4 is 0.83143108647.
    EXPECT_NEAR(noncentral_chi_square_cdf(10.0, 2, 4.0), 0.83143108647, 1e-9);
}

}  // namespace
}  // namespace tlsmon::registration
