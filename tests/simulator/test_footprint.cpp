// The beam footprint and the signal-dependent range noise: mixed pixels at the pier's
// silhouette, black checker squares noisier than white ones by the modelled ratio, and a
// black/white edge band-limited over the footprint's width.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "simulator/footprint.hpp"
#include "simulator/range_noise.hpp"
#include "simulator/render.hpp"
#include "simulator/truth.hpp"

namespace tlsmon::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Site still_small() {
    Site s = preset_small();
    s.drift.enabled = false;
    s.deformation.enabled = false;
    s.atmosphere.enabled = false;  // ranges on the surfaces (the air scales them by ppm)
    return s;
}

// Distance of a point to the nearest surface of the (undeformed) small scene: the ground,
// the pier box, the sphere and checkerboard targets.
double off_surface(const Site& s, const Eigen::Vector3d& p) {
    double d = std::abs(p.z());
    const Pier& b = s.pier;
    const Eigen::Vector3d lo(b.x0, b.y0, 0.0), hi(b.x1, b.y1, b.height);
    const Eigen::Vector3d out = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
    const double inside = std::min({p.x() - lo.x(), hi.x() - p.x(), p.y() - lo.y(), hi.y() - p.y(),
                                    p.z() - lo.z(), hi.z() - p.z()});
    d = std::min(d, out.norm() > 0.0 ? out.norm() : inside);
    for (const Target& t : s.targets) {
        if (t.kind == Target::Kind::sphere) {
            d = std::min(d, std::abs((p - t.centre).norm() - t.radius));
        } else {
            Eigen::Vector3d n = s.scanner.position - t.centre;
            n.z() = 0.0;
            n.normalize();
            const Eigen::Vector3d q = p - t.centre;
            if (std::abs(q.z()) <= 0.5 * t.size + 0.01) d = std::min(d, std::abs(n.dot(q)));
        }
    }
    return d;
}

double azimuth_deg(const Eigen::Vector3d& v) {
    return std::atan2(v.y(), v.x()) / kDeg;
}
double elevation_deg(const Eigen::Vector3d& v) {
    return std::atan2(v.z(), std::hypot(v.x(), v.y())) / kDeg;
}

// The pier's east edge (x1, y0) seen at 48 m with the ground 50–300 m behind it below the
// horizon: footprints straddling it return a range between the two (noise off, so any
// point off every surface is a mixed pixel). The south face's interior has none.
TEST(SimulatorFootprint, MixedPixelsAtThePierSilhouetteOnlyThere) {
    Site s = still_small();
    s.noise.enabled = false;
    s.scanner.azimuth_min_deg = 68.5;  // the east edge is at 69.3°
    s.scanner.azimuth_max_deg = 72.0;
    s.scanner.elevation_min_deg = -2.0;  // the pier's foot is at −1.8°
    s.scanner.elevation_max_deg = 3.0;
    s.scanner.azimuth_step_deg = 0.01;  // 8.4 mm at 48 m; footprint radius 9 mm there
    s.scanner.elevation_step_deg = 0.01;
    const RenderedScan r = render_epoch(s, 0, 0.0);
    const nlohmann::json truth = truth_json(s, 0, 0.0, 0, &r);
    const Eigen::Vector3d o = s.scanner.position;
    const double edge_az = azimuth_deg(Eigen::Vector3d(s.pier.x1, s.pier.y0, 0.0) - o);
    std::size_t near_edge = 0, face_interior = 0, off_interior = 0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        const Eigen::Vector3d& p = r.scan.xyz[i];
        const double az = azimuth_deg(p - o), el = elevation_deg(p - o);
        const double off = off_surface(s, p);
        if (std::abs(az - edge_az) < 0.05 && el < 0.0 && off > 0.01) ++near_edge;
        if (az > edge_az + 0.3 && el > 0.5) {  // the south face, with sky nowhere near
            ++face_interior;
            if (off > 1e-3) ++off_interior;
        }
    }
    // Expected: about 2 straddling cells in each of the ~180 rows with ground behind.
    EXPECT_GT(truth["scan"]["mixed_pixels"].get<std::uint64_t>(), 100u);
    EXPECT_GT(near_edge, 100u);
    ASSERT_GT(face_interior, 50'000u);
    EXPECT_EQ(off_interior, 0u);
}

// A zoomed scan of checkerboard T2 (26 m, head-on) at 0.005° (2.3 mm): footprint radius
// 0.5 · (3.5 mm + 0.3 mrad · 26 m) = 5.65 mm, about 2.5 cells.
Site checkerboard_closeup() {
    Site s = still_small();
    s.scanner.azimuth_min_deg = 67.4;  // T2 at 68.0°, −0.66°, 0.88° wide
    s.scanner.azimuth_max_deg = 68.6;
    s.scanner.elevation_min_deg = -1.2;
    s.scanner.elevation_max_deg = -0.1;
    s.scanner.azimuth_step_deg = 0.005;
    s.scanner.elevation_step_deg = 0.005;
    return s;
}

const Target& board(const Site& s) {
    return s.targets.at(1);  // T2
}

bool on_board(const Site& s, const Eigen::Vector3d& p) {
    const Target& t = board(s);
    Eigen::Vector3d n = s.scanner.position - t.centre;
    n.z() = 0.0;
    n.normalize();
    return std::abs(n.dot(p - t.centre)) < 1e-3 && (p - t.centre).norm() < 0.75 * t.size;
}

// Range noise from the signal: σ_black / σ_white = σ(r, 0.05 cos α) / σ(r, 0.85 cos α)
// (2.2 with the defaults); the constant model would give 1. Each square's σ is estimated
// from n ≈ 10⁴ cells, relative standard error 1/√(2n) ≈ 0.7 %: 5 standard errors of the
// ratio allow 5 %.
TEST(SimulatorFootprint, BlackCheckerSquaresAreNoisierByTheModelledRatio) {
    Site s = checkerboard_closeup();
    s.noise.enabled = false;
    const Scan free = render_epoch(s, 0, 0.0).scan;
    Site noisy = s;
    noisy.noise.enabled = true;
    noisy.noise.angular_arcsec = 0.0;  // the same footprints: r − r_free is the range noise
    const Scan scan = render_epoch(noisy, 0, 0.0).scan;
    ASSERT_EQ(scan.size(), free.size());

    const Eigen::Vector3d o = s.scanner.position;
    const Target& t = board(s);
    const Eigen::Vector3d to = t.centre - o;
    Eigen::Vector3d n = -to;
    n.z() = 0.0;
    const double cos_i = std::abs(n.normalized().dot(to.normalized()));
    const double range = to.norm();
    // Footprints entirely on one colour: albedo 0.05 or 0.85 · e^(−r/400) · cos α (±1 %;
    // over the board r and α change the intensity by < 0.01 %).
    const double fall = std::exp(-range / s.texture.range_attenuation) * cos_i;
    const auto pure = [&](float intensity, double albedo) {
        return std::abs(intensity / (albedo * fall) - 1.0) < 0.01;
    };
    double n_black = 0, ss_black = 0, n_white = 0, ss_white = 0;
    for (std::size_t i = 0; i < free.size(); ++i) {
        if (!on_board(s, free.xyz[i])) continue;
        const double dr = (scan.xyz[i] - o).norm() - (free.xyz[i] - o).norm();
        if (pure(free.intensity[i], 0.05)) {
            ++n_black;
            ss_black += dr * dr;
        } else if (pure(free.intensity[i], 0.85)) {
            ++n_white;
            ss_white += dr * dr;
        }
    }
    ASSERT_GT(n_black, 5'000);
    ASSERT_GT(n_white, 5'000);
    const double s_black = range_sigma(s.noise, range, 0.05 * cos_i);
    const double s_white = range_sigma(s.noise, range, 0.85 * cos_i);
    const double sd_black = std::sqrt(ss_black / n_black), sd_white = std::sqrt(ss_white / n_white);
    EXPECT_NEAR(sd_white, s_white, 5.0 * s_white / std::sqrt(2.0 * n_white));
    EXPECT_NEAR(sd_black, s_black, 5.0 * s_black / std::sqrt(2.0 * n_black));
    const double tol =
        5.0 * std::hypot(1.0 / std::sqrt(2.0 * n_black), 1.0 / std::sqrt(2.0 * n_white));
    EXPECT_NEAR(sd_black / sd_white, s_black / s_white, tol * s_black / s_white);
    EXPECT_GT(sd_black / sd_white, 2.0);
}

// The footprint band-limits the texture: across the board's vertical black/white edge the
// intensity passes from 10 % to 90 % of its step over about the footprint's diameter
// (2 × 5.65 mm = 11.3 mm, 5 cells), not in one cell as a thin ray does. Counted per row
// in the lower half of the board and averaged.
TEST(SimulatorFootprint, FootprintBandLimitsACheckerEdge) {
    Site s = checkerboard_closeup();
    s.noise.enabled = false;
    const Scan scan = render_epoch(s, 0, 0.0).scan;
    const Target& t = board(s);
    const Eigen::Vector3d o = s.scanner.position;
    // Cells of the lower half, 3–17 cm below the centre: white (left) | black (right).
    std::map<std::uint32_t, std::vector<float>> rows;
    float lo = 1.0f, hi = 0.0f;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Vector3d q = scan.xyz[i] - t.centre;
        if (!on_board(s, scan.xyz[i]) || q.z() > -0.03 || q.z() < -0.17) continue;
        rows[scan.grid->row[i]].push_back(scan.intensity[i]);
        lo = std::min(lo, scan.intensity[i]);
        hi = std::max(hi, scan.intensity[i]);
    }
    ASSERT_GT(rows.size(), 50u);
    double transition_cells = 0;
    for (const auto& [row, values] : rows) {
        for (const float v : values) {
            if (v > lo + 0.1f * (hi - lo) && v < lo + 0.9f * (hi - lo)) ++transition_cells;
        }
    }
    const double per_row = transition_cells / rows.size();
    const double spacing = (t.centre - o).norm() * s.scanner.azimuth_step_deg * kDeg;
    const double diameter = 2.0 * footprint_radius(s.beam, (t.centre - o).norm());
    EXPECT_GT(per_row * spacing, 0.5 * diameter) << per_row << " cells per row";
    EXPECT_LT(per_row * spacing, 1.5 * diameter) << per_row << " cells per row";

    Site thin = s;
    thin.beam.footprint = false;
    const Scan sharp = render_epoch(thin, 0, 0.0).scan;
    std::size_t grey = 0;
    for (std::size_t i = 0; i < sharp.size(); ++i) {
        if (!on_board(s, sharp.xyz[i])) continue;
        if (sharp.intensity[i] > lo + 0.1f * (hi - lo) &&
            sharp.intensity[i] < lo + 0.9f * (hi - lo)) {
            ++grey;
        }
    }
    EXPECT_EQ(grey, 0u);  // a thin ray sees black or white, nothing between
}

}  // namespace
}  // namespace tlsmon::sim
