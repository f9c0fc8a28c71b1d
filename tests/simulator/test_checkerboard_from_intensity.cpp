// Acceptance (issue 9): a checkerboard centre estimated from intensity on `pier` is within
// 0.5 mm of the truth. Every checkerboard target of the preset, noise on (range, angle,
// intensity), drift off (the points are then in the true frame, as after a perfect
// registration) and the atmosphere's range scale taken out, the search started 2–3 cm off
// the true centre.
//
// To keep the test fast each target is rendered alone (narrow_window.hpp: the `pier`
// preset's angular step and geometry, a window of ±0.6 board sizes about the target).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "algorithms/registration/checkerboard_centre.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "simulator/truth.hpp"
#include "tests/simulator/narrow_window.hpp"

namespace tlsmon::sim {
namespace {

Eigen::Vector3d vec(const nlohmann::json& j) {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

TEST(SimulatorAcceptance, CheckerboardCentreFromIntensityMatchesTheTruth) {
    Site s = preset_pier();
    s.drift.enabled = false;
    const EpochConditions cond = epoch_conditions(s, 0, 0.0);
    const nlohmann::json truth = truth_json(s, 0, 0.0, cond.utc, nullptr);
    std::size_t boards = 0;
    for (const auto& t : truth.at("targets")) {
        if (t.at("kind").get<std::string>() != "checkerboard") continue;
        const Eigen::Vector3d centre = vec(t.at("centre"));
        const double size = t.at("size").get<double>();
        Site w = s;
        const double range = (centre - s.scanner.position).norm();
        test::narrow_window(w.scanner, centre, 0.6 * size / range * 180.0 / std::numbers::pi);
        Scan scan = render_epoch(w, cond, 2).scan;
        // The atmosphere's range scale taken out (as the pipeline will, from the meteo file;
        // here from the truth), about the scanner, whose pose is exact with drift off.
        for (Eigen::Vector3d& p : scan.xyz) {
            p = s.scanner.position + (p - s.scanner.position) / cond.atmosphere.range_scale;
        }

        CheckerboardSearch q;
        q.approximate_centre = centre + Eigen::Vector3d(0.02, -0.015, 0.01);
        q.size = size;
        q.viewpoint = s.scanner.position;
        const CheckerboardCentre c = checkerboard_centre(scan.xyz, scan.intensity, q);
        const Eigen::Vector3d error = c.centre - centre;
        const Eigen::Vector3d n = vec(t.at("normal"));
        const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(n).normalized();
        const auto sd = [&](const Eigen::Vector3d& a) {
            return std::sqrt(a.dot(c.covariance * a));
        };
        std::printf(
            "%s at %.1f m: %zu points, error %.3f mm (across %.3f, up %.3f, normal %.3f), "
            "σ (%.3f, %.3f, %.3f) mm, blur %.1f mm\n",
            t.at("name").get<std::string>().c_str(), range, c.fit_points, 1e3 * error.norm(),
            1e3 * across.dot(error), 1e3 * error.z(), 1e3 * n.dot(error), 1e3 * sd(across),
            1e3 * sd(Eigen::Vector3d::UnitZ()), 1e3 * sd(n), 1e3 * c.blur_sigma);
        EXPECT_LT(error.norm(), 0.0005) << t.at("name");
        ++boards;
    }
    EXPECT_GE(boards, 2u);
}

// The centre's σ along the board's normal (the plane's offset, s0²/Σw) against what it
// repeats to over seeded noise: every board of `pier`, 200 noise seeds each (2001–2200; the
// weighted fit's wide window was looked at on seeds 1001–1120, where two, three and five
// windows gave the same). With the plane iterated to its own window alone RMS(error/σ) was
// 1.08–1.21, with one wider last window 1.00–1.13 here, weighted by colour 0.97–1.05 with an
// offset error 28–36 % smaller (checkerboard_centre.hpp, step 1). Over 200 seeds an honest
// σ's RMS(error/σ) scatters by ±0.05 per board and ±0.025 pooled.
TEST(SimulatorAcceptance, CheckerboardSigmaAlongTheNormalIsWhatTheCentreRepeatsTo) {
    Site s = preset_pier();
    s.drift.enabled = false;
    s.atmosphere.enabled = false;
    const EpochConditions cond = epoch_conditions(s, 0, 0.0);
    const nlohmann::json truth = truth_json(s, 0, 0.0, cond.utc, nullptr);
    double pooled = 0.0;
    int figures = 0;
    for (const auto& t : truth.at("targets")) {
        if (t.at("kind").get<std::string>() != "checkerboard") continue;
        const Eigen::Vector3d centre = vec(t.at("centre"));
        const double size = t.at("size").get<double>();
        const double range = (centre - s.scanner.position).norm();
        double z2 = 0.0, bias = 0.0;
        int n = 0;
        double e2 = 0.0;
        for (std::uint64_t seed = 2001; seed <= 2200; ++seed) {
            Site w = s;
            w.noise.seed = seed;
            test::narrow_window(w.scanner, centre, 0.6 * size / range * 180.0 / std::numbers::pi);
            const Scan scan = render_epoch(w, cond, 2).scan;
            CheckerboardSearch q;
            q.approximate_centre = centre + Eigen::Vector3d(0.02, -0.015, 0.01);
            q.size = size;
            q.viewpoint = s.scanner.position;
            const CheckerboardCentre c = checkerboard_centre(scan.xyz, scan.intensity, q);
            const double e = c.normal.dot(c.centre - centre);
            z2 += e * e / c.normal.dot(c.covariance * c.normal);
            bias += e;
            e2 += e * e;
            ++n;
        }
        const double rms_z = std::sqrt(z2 / n);
        std::printf(
            "%s at %.1f m: RMS(error/σ) along the normal %.2f, mean error %+.4f mm, RMS error %.4f "
            "mm\n",
            t.at("name").get<std::string>().c_str(), range, rms_z, 1e3 * bias / n,
            1e3 * std::sqrt(e2 / n));
        EXPECT_GT(rms_z, 0.85) << t.at("name");
        EXPECT_LT(rms_z, 1.10) << t.at("name");
        EXPECT_LT(std::abs(bias / n), 1e-5) << t.at("name");
        pooled += z2;
        figures += n;
    }
    ASSERT_EQ(figures, 800);
    const double rms_pooled = std::sqrt(pooled / figures);
    EXPECT_GT(rms_pooled, 0.92);
    EXPECT_LT(rms_pooled, 1.05);
}

}  // namespace
}  // namespace tlsmon::sim
