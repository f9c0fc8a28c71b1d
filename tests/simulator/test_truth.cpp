// The truth file agrees with the models and with the rendered data: displacements at named
// points follow the thermal bending equation, a knocked target's centre moves 10 mm, and
// the reported pose error maps the header coordinates onto the true scene.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "simulator/render.hpp"
#include "simulator/series.hpp"

namespace tlsmon::sim {
namespace {

constexpr std::int64_t kStart = 1780293600;  // 2026-06-01T06:00:00Z
constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Vector3d vec(const nlohmann::json& j) {
    return Eigen::Vector3d(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

Eigen::Affine3d affine(const nlohmann::json& rows) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = rows[r][c].get<double>();
    return Eigen::Affine3d(m);
}

TEST(SimulatorTruth, SampledDisplacementsFollowThermalBending) {
    const Site s = preset_small();
    // Epoch 24 at a 15 min cadence is 12:00 UTC, the south face in the midday sun.
    const EpochFiles f = simulate_epoch(s, 24, kStart, 2);
    const auto& j = f.truth;
    EXPECT_NEAR(j["hours_since_first_epoch"].get<double>(), 6.0, 1e-12);
    const auto& d = j["deformation"];
    // κ = α ΔT_lagged / b with α = 1e-5/K, b = 15 m across x and 7 m across y.
    const double kx = 1e-5 * d["delta_t_lagged_c"][0].get<double>() / 15.0;
    const double ky = 1e-5 * d["delta_t_lagged_c"][1].get<double>() / 7.0;
    EXPECT_NEAR(d["curvature_per_m"][0].get<double>(), kx, 1e-15);
    EXPECT_NEAR(d["curvature_per_m"][1].get<double>(), ky, 1e-15);
    const double mean = d["mean_temperature_change_c"].get<double>();
    int checked = 0;
    for (const auto& sample : j["samples"]) {
        const Eigen::Vector3d p = vec(sample["point"]);
        const Eigen::Vector3d u = vec(sample["displacement"]);
        // Constant curvature: u_h = κ z²/2 = κ H²/2 (z/H)²; u_z = α ΔT_mean z.
        EXPECT_NEAR(u.x(), 0.5 * kx * p.z() * p.z(), 1e-12) << sample["name"];
        EXPECT_NEAR(u.y(), 0.5 * ky * p.z() * p.z(), 1e-12) << sample["name"];
        EXPECT_NEAR(u.z(), 1e-5 * mean * p.z(), 1e-12) << sample["name"];
        ++checked;
    }
    EXPECT_GE(checked, 10);
    // At noon the sunlit south face is warmer than the shaded north face, and the top has
    // started to move away from it (north, +y).
    EXPECT_EQ(j["weather"]["sunlit_face"], "south");
    EXPECT_EQ(j["weather"]["shaded_face"], "north");
    EXPECT_GT(j["weather"]["sunlit_face_temperature_c"].get<double>(),
              j["weather"]["shaded_face_temperature_c"].get<double>() + 3.0);
    EXPECT_GT(d["top_displacement_m"][1].get<double>(), 0.002);
}

TEST(SimulatorTruth, KnockedTargetMovesTenMillimetres) {
    Site s = preset_small();
    s.events.knocked_target = 1;
    s.events.knocked_epoch = 4;
    const auto before = simulate_epoch(s, 3, kStart, 2).truth;
    const auto after = simulate_epoch(s, 4, kStart, 2).truth;
    const Eigen::Vector3d c0 = vec(before["targets"][1]["centre"]);
    const Eigen::Vector3d c1 = vec(after["targets"][1]["centre"]);
    EXPECT_NEAR((c1 - c0).norm(), 0.010, 1e-12);
    EXPECT_NEAR((c0 - s.targets[1].centre).norm(), 0.0, 1e-12);
    // The other targets stay.
    for (int k : {0, 2, 3}) {
        EXPECT_EQ(vec(before["targets"][k]["centre"]), vec(after["targets"][k]["centre"]));
    }
    bool listed = false;
    for (const auto& e : after["events"]) listed |= e["type"] == "knocked_target";
    EXPECT_TRUE(listed);
    EXPECT_GE(after["targets"].size(), 4u);
}

// With drift on and noise off, ground points read through the header pose are tilted off
// z = 0; header_to_true from the truth puts them back exactly.
TEST(SimulatorTruth, HeaderToTrueUndoesThePoseError) {
    Site s = preset_small();
    s.noise.enabled = false;
    s.beam.footprint = false;      // exact ranges (a footprint on grazing ground mixes them)
    s.atmosphere.enabled = false;  // and no atmospheric scale
    s.drift.yaw_amplitude_arcsec = 40.0;
    s.drift.tilt_amplitude_arcsec = 60.0;  // 30″ at 2 h: ~5 mm at 34 m
    const EpochFiles f = simulate_epoch(s, 8, kStart, 2);
    const nlohmann::json& sc = f.truth["scanner"];
    EXPECT_GT(std::abs(sc["pose_error"]["yaw_arcsec"].get<double>()), 10.0);
    const Eigen::Affine3d h = affine(sc["header_to_true"]);
    const RenderedScan r = render_epoch(s, 8, 2.0, 2);
    double worst_header = 0.0, worst_true = 0.0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        const Eigen::Vector3d& p = r.scan.xyz[i];
        const double el = cell_elevation(s.scanner, r.scan.grid->row[i]) / kDeg;
        if (el > -2.5) continue;  // ground only
        bool support = false;     // masts and stands reach below −2.5° too
        for (const Target& t : s.targets) support |= (p - t.centre).head<2>().norm() < 1.0;
        if (support) continue;
        worst_header = std::max(worst_header, std::abs(p.z()));
        worst_true = std::max(worst_true, std::abs((h * p).z()));
    }
    EXPECT_GT(worst_header, 2e-3);  // the error is visible in header coordinates
    EXPECT_LT(worst_true, 1e-9);
}

// Yaw alone (the ground test above cannot see it): the scanner head turned by ψ about its
// standing axis, so a point at horizontal angle φ in the project frame is read at φ − ψ.
// header_to_true must be the rotation by +ψ about the station's vertical (x, y of a south
// face point move by r·ψ ≈ 4 mm for 50″ at 17 m off the y axis), and the
// reported yaw must have that sign.
TEST(SimulatorTruth, HeaderToTrueTurnsByTheReportedYaw) {
    Site s = preset_small();
    s.noise.enabled = false;
    s.beam.footprint = false;  // exact ranges: one thin ray per cell
    s.atmosphere.enabled = false;
    s.deformation.enabled = false;
    s.drift = {};
    s.drift.yaw_amplitude_arcsec = 50.0;
    s.drift.yaw_jitter_arcsec = 0.0;
    s.drift.tilt_amplitude_arcsec = 0.0;
    s.drift.tilt_jitter_arcsec = 0.0;
    s.drift.translation_sigma = 0.0;
    const EpochFiles f = simulate_epoch(s, 24, kStart, 2);  // 6 h: ψ = 50″ · sin(π/2)
    const nlohmann::json& sc = f.truth["scanner"];
    const double yaw = sc["pose_error"]["yaw_arcsec"].get<double>();
    EXPECT_NEAR(yaw, 50.0, 1e-9);
    const Eigen::Affine3d h = affine(sc["header_to_true"]);
    const double psi = yaw * kDeg / 3600.0;
    EXPECT_NEAR(std::atan2(h.linear()(1, 0), h.linear()(0, 0)), psi, 1e-12);
    const RenderedScan r = render_epoch(s, 24, 6.0, 2);
    const Eigen::Vector3d o = s.scanner.position;
    std::size_t n = 0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        const Eigen::Vector3d& p = r.scan.xyz[i];
        if (p.z() < 1.0 || std::abs(p.y() - s.pier.y0) > 0.1) continue;  // south face
        if (p.x() < s.pier.x0 + 0.5 || p.x() > s.pier.x1 - 0.5) continue;
        // Header coordinates: the true point turned by −ψ about the station.
        const Eigen::Vector3d t = h * p;
        ASSERT_NEAR(t.y(), s.pier.y0, 1e-9);
        const Eigen::Vector3d turned = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) * (p - o);
        ASSERT_LT((t - o - turned).norm(), 1e-9);
        ++n;
    }
    EXPECT_GT(n, 30'000u);
}

TEST(SimulatorTruth, MissingAndCutShortEpochs) {
    Site s = preset_small();
    s.events.missing_epochs = {2};
    s.events.cut_short_epoch = 3;
    const EpochFiles missing = simulate_epoch(s, 2, kStart, 2);
    EXPECT_TRUE(missing.missing);
    EXPECT_TRUE(missing.ptx.empty());
    const EpochFiles whole = simulate_epoch(s, 4, kStart, 2);
    const EpochFiles cut = simulate_epoch(s, 3, kStart, 2);
    EXPECT_TRUE(cut.cut_short);
    EXPECT_LT(cut.ptx.size(), whole.ptx.size() * 6 / 10);
    EXPECT_GT(cut.ptx.size(), whole.ptx.size() * 4 / 10);
    EXPECT_EQ(cut.ptx.back(), '\n');
}

}  // namespace
}  // namespace tlsmon::sim
