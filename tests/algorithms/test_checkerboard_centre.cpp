// Known answers for the checkerboard centre: synthetic scans of a vertical 0.40 m board
// 30 m from a scanner, points on a jittered 8 mm lattice, the intensity of a 2×2 checker
// blurred by a Gaussian beam (σ 4 mm) plus noise, the points placed 0.4 mm off where their
// intensity was sampled (angular noise), range noise along the beam, and a few mixed
// pixels behind the rim. The centre comes back to a small fraction of the spacing,
// and its σ is honest: over seeded trials the error lies within 2σ in ≥ 90 % of them and
// within 1σ in about 68 %.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "algorithms/registration/checkerboard_centre.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

struct Board {
    Eigen::Vector3d centre{11.0, 28.0, 1.2};
    double size = 0.40;
    double rotation_deg = 0.0;  // of the pattern in the board's plane
    double blur = 0.004;        // m, σ of the beam
    double dark = 0.05, bright = 0.70;
    double intensity_sigma = 0.01;
    double range_sigma = 0.0005;  // m
    // In-plane offset between where the intensity is sampled and where the point is placed
    // (the beam's angular noise: 3″ at 30 m), m.
    double position_sigma = 0.0004;
    double spacing = 0.008;  // m
};

struct Scanned {
    std::vector<Eigen::Vector3d> xyz;
    std::vector<float> intensity;
    Eigen::Vector3d across, up;  // the board's horizontal and vertical axes
};

Scanned scan_board(const Board& b, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    const Eigen::Vector3d scanner(0.0, 0.0, 1.5);
    Eigen::Vector3d n = scanner - b.centre;
    n.z() = 0.0;
    n.normalize();
    Scanned s;
    s.across =
        Eigen::Vector3d::UnitZ().cross(n).normalized();  // to the right, seen from the scanner
    s.up = Eigen::Vector3d::UnitZ();
    const double th = b.rotation_deg * std::numbers::pi / 180.0;
    const double k = 1.0 / (std::numbers::sqrt2 * b.blur);
    const double mid = 0.5 * (b.dark + b.bright), half = 0.5 * (b.bright - b.dark);
    const int count = static_cast<int>(b.size / b.spacing);
    for (int i = -count; i <= count; ++i) {
        for (int j = -count; j <= count; ++j) {
            const double a = (i + jitter(rng)) * b.spacing, c = (j + jitter(rng)) * b.spacing;
            if (std::abs(a) > 0.5 * b.size || std::abs(c) > 0.5 * b.size) continue;
            const Eigen::Vector3d p = b.centre + a * s.across + c * s.up;
            const double ap = std::cos(th) * a + std::sin(th) * c;
            const double cp = -std::sin(th) * a + std::cos(th) * c;
            const double i0 = mid + half * std::erf(ap * k) * std::erf(cp * k);
            const Eigen::Vector3d beam = (p - scanner).normalized();
            const Eigen::Vector3d placed =
                p + b.position_sigma * (gauss(rng) * s.across + gauss(rng) * s.up);
            s.xyz.push_back(placed + b.range_sigma * gauss(rng) * beam);
            s.intensity.push_back(static_cast<float>(i0 + b.intensity_sigma * gauss(rng)));
        }
    }
    // Mixed pixels between the rim and the background, 5–30 cm behind the board.
    for (int m = 0; m < 40; ++m) {
        const double a = (m % 2 ? 1 : -1) * 0.2, c = -0.2 + 0.01 * m;
        const Eigen::Vector3d p = b.centre + a * s.across + c * s.up;
        const Eigen::Vector3d beam = (p - scanner).normalized();
        s.xyz.push_back(p + (0.05 + 0.25 * (m % 7) / 6.0) * beam);
        s.intensity.push_back(0.3f);
    }
    return s;
}

TEST(CheckerboardCentre, NoiseFreeBoardGivesTheCentreExactly) {
    Board b;
    b.intensity_sigma = 0.0;
    b.range_sigma = 0.0;
    b.position_sigma = 0.0;
    const Scanned s = scan_board(b, 1);
    CheckerboardSearch q;
    q.viewpoint = {0.0, 0.0, 1.5};
    q.approximate_centre = b.centre + Eigen::Vector3d(0.02, -0.01, -0.025);
    const CheckerboardCentre c = checkerboard_centre(s.xyz, s.intensity, q);
    EXPECT_LT((c.centre - b.centre).norm(), 1e-6);
    EXPECT_NEAR(c.blur_sigma, b.blur, 1e-6);
    EXPECT_NEAR(c.dark, b.dark, 1e-6);
    EXPECT_NEAR(c.bright, b.bright, 1e-6);
    EXPECT_NEAR(std::abs(c.normal.dot(s.across.cross(s.up))), 1.0, 1e-9);
}

TEST(CheckerboardCentre, RotatedPatternAndSwappedColours) {
    for (const double deg : {20.0, -35.0, 80.0}) {
        Board b;
        b.rotation_deg = deg;
        b.intensity_sigma = 0.0;
        b.range_sigma = 0.0;
        b.position_sigma = 0.0;
        const Scanned s = scan_board(b, 2);
        CheckerboardSearch q;
        q.viewpoint = {0.0, 0.0, 1.5};
        q.approximate_centre = b.centre + Eigen::Vector3d(-0.015, 0.0, 0.02);
        const CheckerboardCentre c = checkerboard_centre(s.xyz, s.intensity, q);
        EXPECT_LT((c.centre - b.centre).norm(), 1e-6) << deg;
        // Within ±45°: 80° is −10° with the colours swapped.
        const double expected = deg > 45.0 ? deg - 90.0 : deg;
        EXPECT_NEAR(c.rotation * 180.0 / std::numbers::pi, expected, 1e-4) << deg;
    }
}

TEST(CheckerboardCentre, SigmaIsHonestOverSeededTrials) {
    const Board b;
    int within2 = 0, within1 = 0, checks = 0;
    double worst = 0.0;
    for (std::uint64_t seed = 1; seed <= 100; ++seed) {
        const Scanned s = scan_board(b, seed);
        CheckerboardSearch q;
        q.viewpoint = {0.0, 0.0, 1.5};
        q.approximate_centre = b.centre + Eigen::Vector3d(0.01, 0.01, 0.01);
        const CheckerboardCentre c = checkerboard_centre(s.xyz, s.intensity, q);
        const Eigen::Vector3d e = c.centre - b.centre;
        worst = std::max(worst, e.norm());
        // Per axis of the board: across, up, and along the normal.
        for (const Eigen::Vector3d& axis : {s.across, s.up, s.across.cross(s.up)}) {
            const double err = std::abs(axis.dot(e));
            const double sd = std::sqrt(axis.dot(c.covariance * axis));
            ++checks;
            if (err <= 2.0 * sd) ++within2;
            if (err <= sd) ++within1;
        }
    }
    std::printf("within 2σ: %d, within 1σ: %d of %d; largest error %.3f mm\n", within2, within1,
                checks, 1e3 * worst);
    // Expected 95.4 % and 68.3 %; 300 checks (partly correlated): wide bounds.
    EXPECT_GE(within2, 0.90 * checks) << within2 << " of " << checks;
    EXPECT_GE(within1, 0.55 * checks) << within1 << " of " << checks;
    EXPECT_LE(within1, 0.82 * checks) << within1 << " of " << checks;
    EXPECT_LT(worst, 2.5e-4);  // 0.25 mm, 1/30 of the point spacing
}

TEST(CheckerboardCentre, UndersampledPatternIsRefused) {
    // A 1 m board 100 m away at 0.03°: points 52 mm apart, the beam's blur σ 8 mm (ratio
    // 0.15): most rows across an edge hold no mixed return; refused, not guessed.
    Board far;
    far.size = 1.0;
    far.blur = 0.008;
    far.spacing = 0.052;
    CheckerboardSearch q;
    q.viewpoint = {0.0, 0.0, 1.5};
    q.size = far.size;
    q.approximate_centre = far.centre + Eigen::Vector3d(0.01, 0.0, -0.01);
    const Scanned s = scan_board(far, 5);
    try {
        checkerboard_centre(s.xyz, s.intensity, q);
        ADD_FAILURE() << "an undersampled board gave a centre";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("undersampled"), std::string::npos) << e.what();
    }
    // The same board with its points 24 mm apart (ratio 0.33): resolved.
    far.spacing = 0.024;
    const Scanned fine = scan_board(far, 6);
    const CheckerboardCentre c = checkerboard_centre(fine.xyz, fine.intensity, q);
    EXPECT_NEAR(c.point_spacing, 0.024, 0.004);
    EXPECT_LT((c.centre - far.centre).norm(), 0.003);
}

TEST(CheckerboardCentre, TooFewPointsOrBadInputIsAnError) {
    Board b;
    const Scanned s = scan_board(b, 3);
    CheckerboardSearch q;
    q.viewpoint = {0.0, 0.0, 1.5};
    q.approximate_centre = b.centre + Eigen::Vector3d(5.0, 0.0, 0.0);  // nothing there
    EXPECT_THROW(checkerboard_centre(s.xyz, s.intensity, q), Error);
    q.approximate_centre = b.centre;
    EXPECT_THROW(checkerboard_centre(s.xyz, {}, q), Error);
    q.size = 0.0;
    EXPECT_THROW(checkerboard_centre(s.xyz, s.intensity, q), Error);
}

}  // namespace
}  // namespace tlsmon::test
