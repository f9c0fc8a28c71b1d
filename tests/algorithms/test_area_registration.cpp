// The local registration of an area (algorithms/vectors/area_registration.hpp) against known
// answers: a textured patch sampled twice on jittered grids, the second moved by a known
// vector, its radiometry scaled and offset, both with noise. The vector is recovered with the
// motion along the surface as well as along the normal; over independent draws the errors
// fall within the cluster-robust covariance at its nominal rate (the covariance is honest,
// not only small); a patch without texture or relief leaves the motion along the surface
// unobserved, and its covariance says so.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "algorithms/vectors/area_registration.hpp"
#include "core/error.hpp"

namespace tlsmon::vectors {
namespace {

// A concrete-like intensity texture: sinusoids of 6–30 cm wavelength in random directions.
struct Texture {
    std::vector<Eigen::Vector3d> waves;  // (k_u, k_v, phase)
    std::vector<double> amplitude;
    explicit Texture(unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        for (int k = 0; k < 16; ++k) {
            const double wavelength = 0.06 + 0.24 * U(rng), angle = 2 * std::numbers::pi * U(rng);
            const double kk = 2 * std::numbers::pi / wavelength;
            waves.emplace_back(kk * std::cos(angle), kk * std::sin(angle),
                               2 * std::numbers::pi * U(rng));
            amplitude.push_back(0.05 * (0.5 + U(rng)));
        }
    }
    double operator()(double u, double v) const {
        double f = 0.45;
        for (std::size_t k = 0; k < waves.size(); ++k)
            f += amplitude[k] * std::sin(waves[k].x() * u + waves[k].y() * v + waves[k].z());
        return f;
    }
};

struct Surface {
    Texture texture{1};
    bool textured = true;
};

// Samples on a grid of `spacing` (jittered by a quarter of it) over [0, 1]², the
// surface seen moved by `t` with gain g and offset c; N(0, σ_w) heights, N(0, σ_I) intensity.
std::vector<AreaSample> sample(const Surface& s, const Eigen::Vector3d& t, double g, double c,
                               std::mt19937& rng, double spacing = 0.01, double sigma_w = 0.0008,
                               double sigma_i = 0.01) {
    std::normal_distribution<double> n01(0.0, 1.0);
    std::uniform_real_distribution<double> jitter(-0.25 * spacing, 0.25 * spacing);
    std::vector<AreaSample> out;
    for (double u = 0.5 * spacing; u < 1.0; u += spacing)
        for (double v = 0.5 * spacing; v < 1.0; v += spacing) {
            const double pu = u + jitter(rng), pv = v + jitter(rng);
            const double su = pu - t.x(), sv = pv - t.y();  // the surface point seen there
            const double I = s.textured ? s.texture(su, sv) : 0.45;
            out.push_back({float(pu), float(pv), float(t.z() + sigma_w * n01(rng)),
                           float(g * I + c + sigma_i * n01(rng))});
        }
    return out;
}

TEST(AreaRegistration, RecoversAKnownVectorAlongTheSurfaceAndTheNormal) {
    std::mt19937 rng(11);
    const Surface s;
    const Eigen::Vector3d t(0.004, -0.0025, 0.003);
    const auto reference = sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng);
    const auto epoch = sample(s, t, 1.1, -0.02, rng);
    const AreaVector r = register_area(reference, epoch);
    ASSERT_TRUE(r.measured()) << outcome_name(r.outcome);
    const Eigen::Vector3d sigma = r.covariance.diagonal().cwiseSqrt();
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(r.displacement(k), t(k), 4 * sigma(k)) << "component " << k;
        EXPECT_LT(sigma(k), 0.0002) << "component " << k;  // 0.2 mm from 10,000 samples
    }
    EXPECT_NEAR(r.gain, 1.1, 0.02);
    EXPECT_NEAR(r.offset, -0.02, 0.01);
    EXPECT_NEAR(r.spacing, 0.01, 0.001);
    EXPECT_GT(r.coarse_correlation, 0.8);
    EXPECT_EQ(r.blocks, 16u);  // 0.25 m blocks over 1 m × 1 m
}

TEST(AreaRegistration, MotionOfSeveralSpacingsIsFoundByTheCoarseStep) {
    std::mt19937 rng(12);
    const Surface s;
    const Eigen::Vector3d t(-0.025, 0.02, -0.002);  // three spacings along the surface
    Parameters search;
    search.search_radius = 0.04;
    const AreaVector r = register_area(sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng),
                                       sample(s, t, 1.0, 0.0, rng), search);
    ASSERT_TRUE(r.measured());
    EXPECT_LT((r.displacement - t).norm(), 0.0005);
    EXPECT_GT(r.coarse_correlation, 0.9);
}

// Over independent draws the errors lie within 2σ of the cluster-robust covariance about
// 95 % of the time in every component, and the covariance is not padded either.
TEST(AreaRegistration, TheCovarianceCoversTheErrorAtItsNominalRate) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> U(-0.006, 0.006);
    int within[3] = {0, 0, 0};
    double ratio2[3] = {0, 0, 0};
    const int draws = 60;
    for (int d = 0; d < draws; ++d) {
        Surface s;
        s.texture = Texture(100 + unsigned(d));
        const Eigen::Vector3d t(U(rng), U(rng), U(rng));
        const AreaVector r = register_area(sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng),
                                           sample(s, t, 1.0, 0.0, rng));
        ASSERT_TRUE(r.measured());
        for (int k = 0; k < 3; ++k) {
            const double z = (r.displacement(k) - t(k)) / std::sqrt(r.covariance(k, k));
            within[k] += std::abs(z) <= 2.0;
            ratio2[k] += z * z / draws;
        }
    }
    for (int k = 0; k < 3; ++k) {
        std::printf("component %d: %d of %d within 2σ, mean z² %.2f\n", k, within[k], draws,
                    ratio2[k]);
        // Binomial(60, 0.954): 52 or more with probability 0.99.
        EXPECT_GE(within[k], 52) << "component " << k;
        EXPECT_GT(ratio2[k], 0.4) << "component " << k;  // not padded by more than ~1.6×
        EXPECT_LT(ratio2[k], 1.8) << "component " << k;
    }
}

TEST(AreaRegistration, WithoutTextureTheMotionAlongTheSurfaceIsUnobserved) {
    std::mt19937 rng(14);
    Surface s;
    s.textured = false;
    const Eigen::Vector3d t(0.003, 0.003, 0.002);
    const auto reference = sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng);
    const auto epoch = sample(s, t, 1.0, 0.0, rng);
    // No vector: along the surface nothing observes it.
    EXPECT_EQ(register_area(reference, epoch).outcome, AreaOutcome::untextured);
    // Asked for one whatever its σ: the normal's, and along the surface the start (the global
    // registration's place) with about the prior's σ.
    Parameters any;
    any.max_sigma = 1.0;
    const AreaVector r = register_area(reference, epoch, any);
    ASSERT_TRUE(r.measured()) << outcome_name(r.outcome);
    EXPECT_NEAR(r.displacement.z(), 0.002, 4 * std::sqrt(r.covariance(2, 2)));
    EXPECT_LT(std::sqrt(r.covariance(2, 2)), 0.0001);
    for (int k = 0; k < 2; ++k) {
        EXPECT_LT(std::abs(r.displacement(k)), 0.001) << "component " << k;
        EXPECT_GT(std::sqrt(r.covariance(k, k)), 0.5 * kPriorSigma) << "component " << k;
    }
}

// A brightness ramp across the area (weathering, moisture, the angle of incidence) moved
// along itself is the same ramp with another offset: it observes nothing either.
TEST(AreaRegistration, ABrightnessRampIsNoTexture) {
    std::mt19937 rng(17);
    std::normal_distribution<double> n01(0.0, 1.0);
    const auto ramp = [&](const Eigen::Vector3d& t) {
        std::vector<AreaSample> out;
        for (double u = 0.005; u < 1.0; u += 0.01)
            for (double v = 0.005; v < 1.0; v += 0.01)
                out.push_back({float(u), float(v), float(t.z() + 0.0008 * n01(rng)),
                               float(0.3 + 0.2 * (u - t.x()) + 0.01 * n01(rng))});
        return out;
    };
    const Eigen::Vector3d t(0.004, 0.0, 0.0);
    EXPECT_EQ(register_area(ramp(Eigen::Vector3d::Zero()), ramp(t)).outcome,
              AreaOutcome::untextured);
}

TEST(AreaRegistration, TooFewSamplesOrBlocksAreSaid) {
    std::mt19937 rng(16);
    const Surface s;
    auto reference = sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng, 0.08);
    EXPECT_EQ(register_area(reference, reference).outcome, AreaOutcome::few_points);
    Parameters p;
    p.block = 0.5;  // four blocks for the whole area
    reference = sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng);
    EXPECT_EQ(
        register_area(reference, sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng), p).outcome,
        AreaOutcome::few_blocks);
    p = Parameters{};
    p.block = 0;
    EXPECT_THROW(register_area(reference, reference, p), Error);
}

// An area across the edge of a detail window: sampled at 8 mm left of `edge` and 18 mm right
// of it (a scan's fine strip and its coarse surroundings). With the scanner's drift the edge
// moves over the surface between epochs; the area gives no vector, not the edge's motion.
std::vector<AreaSample> across_a_window_edge(const Surface& s, double edge, std::mt19937& rng) {
    std::vector<AreaSample> out;
    for (const auto& p : sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng, 0.008))
        if (p.u < edge) out.push_back(p);
    for (const auto& p : sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng, 0.018))
        if (p.u >= edge) out.push_back(p);
    return out;
}

TEST(AreaRegistration, AnAreaAcrossAChangeOfSamplingHasNoVector) {
    std::mt19937 rng(17);
    const Surface s;
    const auto reference = across_a_window_edge(s, 0.50, rng);
    const auto epoch = across_a_window_edge(s, 0.53, rng);
    EXPECT_EQ(register_area(reference, epoch).outcome, AreaOutcome::mixed_sampling);
    EXPECT_STREQ(outcome_name(AreaOutcome::mixed_sampling), "mixed sampling");
    // The coarse part alone, both epochs: uniform, measured, and the motion (none) found.
    std::vector<AreaSample> coarse_r, coarse_e;
    for (const auto& p : reference)
        if (p.u >= 0.53) coarse_r.push_back(p);
    for (const auto& p : epoch)
        if (p.u >= 0.53) coarse_e.push_back(p);
    const AreaVector r = register_area(coarse_r, coarse_e);
    ASSERT_TRUE(r.measured()) << outcome_name(r.outcome);
    EXPECT_LT(r.displacement.head<2>().norm(),
              3 * std::sqrt(r.covariance(0, 0) + r.covariance(1, 1)));
}

TEST(AreaRegistration, ACoarselySampledAreaHasNoVector) {
    std::mt19937 rng(18);
    const Surface s;
    const auto reference = sample(s, Eigen::Vector3d::Zero(), 1.0, 0.0, rng, 0.03);
    const auto epoch = sample(s, Eigen::Vector3d(0.002, 0, 0), 1.0, 0.0, rng, 0.03);
    Parameters p;
    p.max_spacing = 0.02;
    EXPECT_EQ(register_area(reference, epoch, p).outcome, AreaOutcome::undersampled);
    p.max_spacing = 0.04;  // a coarser scanner footprint allowed: measured
    EXPECT_TRUE(register_area(reference, epoch, p).measured());
    p.max_spacing = 0;
    EXPECT_THROW(register_area(reference, epoch, p), Error);
}

}  // namespace
}  // namespace tlsmon::vectors
