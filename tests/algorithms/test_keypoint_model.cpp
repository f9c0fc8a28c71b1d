// Known answers for the keypoint displacement model (step 7 of the Hochmoselbrücke method):
// the least-absolute-residuals bivariate cubic recovers known coefficients despite 15–20 %
// planted outliers — exactly without noise, within the L1 estimator's expected error with
// noise (where ordinary least squares does not) — with t a time or a temperature, far from
// 0 or not; degenerate inputs are undefined with a reason, never NaN silently.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <numbers>
#include <random>

#include "algorithms/keypoints/displacement_model.hpp"
#include "algorithms/registration/distribution_quantiles.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

using keypoints::ModelCoefficients;
using keypoints::ModelObservation;

// c_pq in kModelTerms order (00 10 01 20 11 02 30 21 12 03), t in hours, z in m, d in m:
// a few millimetres over 6 h and 40 m.
ModelCoefficients truth() {
    ModelCoefficients c;
    c << 0.5e-3, 0.2e-3, 0.05e-3, -0.02e-3, 3e-6, -1e-6, 2e-6, 1e-7, -2e-8, 1e-8;
    return c;
}

double cubic(const ModelCoefficients& c, double t, double z) {
    double d = 0;
    for (std::size_t k = 0; k < keypoints::kModelTerms.size(); ++k)
        d += c[static_cast<Eigen::Index>(k)] * std::pow(t, keypoints::kModelTerms[k].p) *
             std::pow(z, keypoints::kModelTerms[k].q);
    return d;
}

// The case study's series: 26 epochs 15 min apart, here 20 segments 2 m apart in height.
std::vector<ModelObservation> series(const ModelCoefficients& c, double t0 = 0) {
    std::vector<ModelObservation> obs;
    for (int e = 0; e < 26; ++e)
        for (int s = 0; s < 20; ++s) {
            const double t = 0.25 * e, z = 1.0 + 2.0 * s;
            obs.push_back({t0 + t, z, cubic(c, t, z)});
        }
    return obs;
}

// Replaces a share of the observations by gross errors of 5–20 mm, either sign.
std::vector<bool> plant_outliers(std::vector<ModelObservation>& obs, double share, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u01(0, 1), size(0.005, 0.020);
    std::vector<bool> planted(obs.size(), false);
    for (std::size_t i = 0; i < obs.size(); ++i)
        if (u01(rng) < share) {
            obs[i].d += (u01(rng) < 0.5 ? -1 : 1) * size(rng);
            planted[i] = true;
        }
    return planted;
}

TEST(KeypointModel, RecoversKnownCoefficientsExactlyDespite15PercentOutliers) {
    const ModelCoefficients c = truth();
    auto obs = series(c);
    const auto planted = plant_outliers(obs, 0.15, 1);
    const auto n_planted = std::count(planted.begin(), planted.end(), true);
    ASSERT_GT(n_planted, 60);  // ≈ 78 of 520

    // Converged far tighter than the default, to show the estimator is exact here.
    keypoints::ModelParameters tight;
    tight.tolerance = 1e-10;
    const auto m = keypoints::fit_displacement_model(obs, tight);
    ASSERT_TRUE(m.defined()) << m.undefined_reason;
    EXPECT_TRUE(m.converged);
    EXPECT_GT(m.iterations, 1u);
    // Noise-free inliers: the L1 fit passes through them; the model equals the truth on the
    // whole grid to well below a micrometre, and the coefficients agree.
    double worst = 0;
    for (int e = 0; e < 26; ++e)
        for (int s = 0; s < 20; ++s) {
            const double t = 0.25 * e, z = 1.0 + 2.0 * s;
            worst = std::max(worst, std::abs(m(t, z) - cubic(c, t, z)));
        }
    EXPECT_LT(worst, 1e-9);
    // Each term's coefficient error times its largest monomial on the grid (t ≤ 6.25 h,
    // z ≤ 39 m): what it adds to d at worst, below 1 nm.
    const ModelCoefficients raw = m.raw_coefficients();
    for (int k = 0; k < 10; ++k) {
        const double largest = std::pow(6.25, keypoints::kModelTerms[k].p) *
                               std::pow(39.0, keypoints::kModelTerms[k].q);
        EXPECT_LT(std::abs(raw[k] - c[k]) * largest, 1e-9) << "term " << k;
    }
    // Residuals: ~0 at the inliers, the planted error at the outliers.
    ASSERT_EQ(m.residuals.size(), static_cast<Eigen::Index>(obs.size()));
    for (std::size_t i = 0; i < obs.size(); ++i) {
        const double expected = obs[i].d - cubic(c, obs[i].t, obs[i].z);
        EXPECT_NEAR(m.residuals[static_cast<Eigen::Index>(i)], expected, 1e-9) << i;
    }
    EXPECT_LT(m.residual_scale, 1e-9);  // most residuals are zero
}

TEST(KeypointModel, WithNoiseAndTwentyPercentOutliersWithinTheL1EstimatorsError) {
    // σ = 0.3 mm on every observation, 20 % gross errors. For least squares the mean squared
    // error of the fitted surface over the design points is σ² p / n; least absolute
    // residuals is π/2 times less efficient for normal errors. Bound: twice that RMS, with n
    // the inliers — while ordinary least squares, thrown off by the outliers, is far outside.
    const ModelCoefficients c = truth();
    auto obs = series(c);
    std::mt19937 rng(17);
    std::normal_distribution<double> noise(0, 0.0003);
    for (auto& o : obs) o.d += noise(rng);
    const auto planted = plant_outliers(obs, 0.20, 2);
    const double n_inliers = static_cast<double>(std::count(planted.begin(), planted.end(), false));

    const auto m = keypoints::fit_displacement_model(obs);
    ASSERT_TRUE(m.defined());
    EXPECT_TRUE(m.converged) << m.iterations << " iterations";
    double squares = 0;
    for (const auto& o : obs) squares += std::pow(m(o.t, o.z) - cubic(c, o.t, o.z), 2);
    const double rms = std::sqrt(squares / static_cast<double>(obs.size()));
    const double bound = 2 * std::sqrt(std::numbers::pi / 2) * 0.0003 * std::sqrt(10 / n_inliers);
    EXPECT_LT(rms, bound);
    // The robust scale of the residuals, 1.4826 · MAD with the outliers counted: with a
    // share f of inliers all nearer than the outliers, MAD = σ Φ⁻¹(½ + ¼/f) (the median of
    // |r| is the (½/f) quantile of the inliers' |r|); the sample MAD of ~400 values is good
    // to ~10 %.
    const double f = n_inliers / static_cast<double>(obs.size());
    const double expected_scale = 1.4826 * 0.0003 * registration::normal_quantile(0.5 + 0.25 / f);
    EXPECT_NEAR(m.residual_scale, expected_scale, 0.15 * expected_scale);

    // Ordinary least squares on the same data, for contrast.
    Eigen::MatrixXd X(static_cast<Eigen::Index>(obs.size()), 10);
    Eigen::VectorXd d(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        const auto& o = obs[static_cast<std::size_t>(i)];
        for (int k = 0; k < 10; ++k)
            X(i, k) = std::pow(o.t, keypoints::kModelTerms[k].p) *
                      std::pow(o.z, keypoints::kModelTerms[k].q);
        d[i] = o.d;
    }
    const Eigen::VectorXd ls = X.colPivHouseholderQr().solve(d);
    double ls_squares = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        const auto& o = obs[static_cast<std::size_t>(i)];
        ls_squares += std::pow(X.row(i).dot(ls) - cubic(c, o.t, o.z), 2);
    }
    EXPECT_GT(std::sqrt(ls_squares / static_cast<double>(X.rows())), 3 * bound);
}

TEST(KeypointModel, TemperatureAndTimesFarFromZeroAreWellConditioned) {
    // t as a temperature from −5 to 25 °C.
    ModelCoefficients c = truth();
    std::vector<ModelObservation> obs;
    for (int e = 0; e < 26; ++e)
        for (int s = 0; s < 20; ++s) {
            const double T = -5 + 30.0 * e / 25, z = 1.0 + 2.0 * s;
            obs.push_back({T, z, 0.1e-3 * T + 1e-6 * T * z + cubic(c, 0, z)});
        }
    const auto mt = keypoints::fit_displacement_model(obs);
    ASSERT_TRUE(mt.defined());
    EXPECT_NEAR(mt(10, 20), 1e-3 + 2e-4 + cubic(c, 0, 20), 1e-10);
    EXPECT_NEAR(mt.raw_coefficients()[1], 0.1e-3, 1e-10);  // t
    EXPECT_NEAR(mt.raw_coefficients()[4], 1e-6, 1e-12);    // t z

    // t in hours since 2000 (≈ 235 000): the monomials of raw t would span 1e16; centred
    // and scaled the fit is as good as near 0.
    const double t0 = 235000;
    auto far = series(c, t0);
    plant_outliers(far, 0.15, 3);
    const auto mf = keypoints::fit_displacement_model(far);
    ASSERT_TRUE(mf.defined());
    EXPECT_NEAR(mf.t_centre, t0 + 3.125, 1e-9);
    EXPECT_NEAR(mf.t_scale, 3.125, 1e-12);
    EXPECT_NEAR(mf.z_centre, 20, 1e-12);
    EXPECT_NEAR(mf.z_scale, 19, 1e-12);
    for (double t : {0.0, 2.0, 6.25})
        for (double z : {1.0, 20.0, 39.0}) EXPECT_NEAR(mf(t0 + t, z), cubic(c, t, z), 1e-8);
}

TEST(KeypointModel, DegenerateInputsAreUndefinedWithAReason) {
    const ModelCoefficients c = truth();
    // Fewer than 10 observations.
    auto few = series(c);
    few.resize(9);
    auto m = keypoints::fit_displacement_model(few);
    EXPECT_FALSE(m.defined());
    EXPECT_NE(m.undefined_reason.find("at least 10"), std::string::npos) << m.undefined_reason;
    EXPECT_TRUE(std::isnan(m.coefficients[0]));  // NaN, and said so by defined()

    // One epoch only: every observation at one t.
    std::vector<ModelObservation> one_t;
    for (int s = 0; s < 20; ++s) one_t.push_back({0.5, 2.0 * s, 0.001 * s});
    m = keypoints::fit_displacement_model(one_t);
    EXPECT_FALSE(m.defined());
    EXPECT_NE(m.undefined_reason.find("carry only 4 of the 10"), std::string::npos)
        << m.undefined_reason;

    // t and z on one line (z = 2t + 1): only polynomials of degree ≤ 3 in t remain.
    std::vector<ModelObservation> line;
    for (int i = 0; i < 30; ++i) line.push_back({0.1 * i, 0.2 * i + 1, 0.001 * i});
    m = keypoints::fit_displacement_model(line);
    EXPECT_FALSE(m.defined());
    EXPECT_NE(m.undefined_reason.find("carry only 4"), std::string::npos) << m.undefined_reason;

    // Three epochs: t³ cannot be told from lower powers.
    std::vector<ModelObservation> three;
    for (int e = 0; e < 3; ++e)
        for (int s = 0; s < 10; ++s) three.push_back({1.0 * e, 1.0 * s, 0});
    EXPECT_FALSE(keypoints::fit_displacement_model(three).defined());

    // All displacements equal: defined, the constant, zero residuals — not NaN.
    auto flat = series(ModelCoefficients::Zero());
    for (auto& o : flat) o.d = 0.002;
    m = keypoints::fit_displacement_model(flat);
    ASSERT_TRUE(m.defined());
    EXPECT_TRUE(m.converged);
    EXPECT_NEAR(m.raw_coefficients()[0], 0.002, 1e-15);
    for (int k = 1; k < 10; ++k) EXPECT_NEAR(m.raw_coefficients()[k], 0, 1e-15);
    EXPECT_NEAR(m.residuals.cwiseAbs().maxCoeff(), 0, 1e-15);
    EXPECT_NEAR(m.residual_scale, 0, 1e-15);

    // Non-finite input is an error naming the observation.
    auto bad = series(c);
    bad[7].d = std::numeric_limits<double>::quiet_NaN();
    try {
        keypoints::fit_displacement_model(bad);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("observation 7"), std::string::npos);
    }
}

}  // namespace
}  // namespace tlsmon::test
