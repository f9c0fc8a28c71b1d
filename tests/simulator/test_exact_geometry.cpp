// Noise-free renders against analytic ranges: the ground plane, the pier's south face,
// the deformed face, a target sphere (also after it is knocked), and the round pier's
// cylinder, upright and leaning after the tilt event.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "simulator/deformation.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/render.hpp"
#include "simulator/terrain.hpp"
#include "simulator/texture.hpp"

namespace tlsmon::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Site noise_free_small() {
    Site s = preset_small();
    s.noise.enabled = false;
    s.drift.enabled = false;
    s.deformation.enabled = false;
    s.atmosphere.enabled = false;  // true ranges (the atmosphere scales them by a few ppm)
    // One thin ray per cell: these tests check the ray caster's geometry, which a footprint
    // would blur (mixed ranges at edges, second-order range bias on grazing surfaces).
    s.beam.footprint = false;
    return s;
}

// Readout direction of a point's cell.
Eigen::Vector3d beam(const Site& s, const Scan& scan, std::size_t i) {
    const double az = cell_azimuth(s.scanner, scan.grid->column[i]);
    const double el = cell_elevation(s.scanner, scan.grid->row[i]);
    return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

TEST(SimulatorExact, GroundAndPierFaceRangesAreAnalytic) {
    const Site s = noise_free_small();
    const Scan scan = render_epoch(s, 0, 0.0).scan;
    const Eigen::Vector3d o = s.scanner.position;
    std::size_t ground = 0, face = 0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Vector3d d = beam(s, scan, i);
        const double r = (scan.xyz[i] - o).norm();
        // Every point lies on its beam.
        ASSERT_LT((scan.xyz[i] - (o + r * d)).norm(), 1e-9);
        if (std::abs(scan.xyz[i].z()) < 1e-6) {
            // Ground z = 0 seen from height h along elevation e: r = h / sin(−e).
            EXPECT_NEAR(r, o.z() / -d.z(), 1e-9);
            ++ground;
        } else if (std::abs(scan.xyz[i].y() - s.pier.y0) < 1e-6) {
            // South face y = y0: r = (y0 − o_y) / d_y.
            EXPECT_NEAR(r, (s.pier.y0 - o.y()) / d.y(), 1e-9);
            EXPECT_GE(scan.xyz[i].x(), s.pier.x0 - 1e-9);
            EXPECT_LE(scan.xyz[i].x(), s.pier.x1 + 1e-9);
            ++face;
        }
    }
    EXPECT_GT(ground, 5'000u);
    EXPECT_GT(face, 30'000u);
}

// The epoch of the first day (15 min cadence) where the pier's top moved farthest: the
// field is largest there, so the geometry below is tested where it matters most.
EpochConditions largest_bending(const Site& s) {
    EpochConditions best;
    for (int epoch = 0; epoch < 96; ++epoch) {
        EpochConditions c = epoch_conditions(s, epoch, epoch * 0.25);
        if (c.bending.top.head<2>().norm() > best.bending.top.head<2>().norm()) best = c;
    }
    return best;
}

// The ray meets the displaced surface: a noise-free point on the south face at height z
// lies on the plane y = y0 + u_y(z), with u_y = κ_y H²/2 (z/H)² from the thermal bending.
TEST(SimulatorExact, DeformedFaceIsWhereTheFieldMovedIt) {
    Site s = noise_free_small();
    s.deformation.enabled = true;
    const EpochConditions c = largest_bending(s);
    // κ_y = α ΔT_y / b_y with the section's lagged temperature difference across y.
    const double kappa_y =
        s.deformation.expansion_coefficient * c.bending.delta_lagged.y() / (s.pier.y1 - s.pier.y0);
    const double top_y = 0.5 * kappa_y * s.pier.height * s.pier.height;
    ASSERT_GT(std::abs(top_y), 0.005);  // a day of sun moves the top by several mm
    const Scan scan = render_epoch(s, c).scan;
    std::size_t n = 0;
    double max_seen = 0.0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Vector3d& p = scan.xyz[i];
        if (p.z() < 0.5 || p.x() < s.pier.x0 + 0.5 || p.x() > s.pier.x1 - 0.5) continue;
        if (std::abs(p.y() - s.pier.y0) > 0.1) continue;  // the south face, near its plane
        // z of the material point differs from p.z by u_z (≤ 6 mm), which changes u_y by
        // 2 u_top z/H² · u_z < 1e-5 m.
        const double zeta = p.z() / s.pier.height;
        EXPECT_NEAR(p.y(), s.pier.y0 + top_y * zeta * zeta, 1e-5) << "z = " << p.z();
        max_seen = std::max(max_seen, std::abs(p.y() - s.pier.y0));
        ++n;
    }
    EXPECT_GT(n, 30'000u);
    EXPECT_GT(max_seen, 0.8 * std::abs(top_y));  // the face near the top moved by ~u_top
}

// The displaced pier ends where its displaced edges are. At the largest bending of the day
// the walls moved by about a centimetre; seen at 87° incidence a normal shift of 10 mm
// moves the hit by ~0.2 m along the ray, so rays near the wall's ends and the top edge must
// be cast against the displaced faces themselves, not against the undeformed box.
TEST(SimulatorExact, DisplacedPierEdgesAreWhereTheFieldMovedThem) {
    Site s = noise_free_small();
    s.deformation.enabled = true;
    const EpochConditions c = largest_bending(s);
    ASSERT_GT(c.bending.top.head<2>().norm(), 0.005);
    const SceneAtEpoch scene(s, c);
    const Eigen::Vector3d o = s.scanner.position;
    const auto displaced = [&](const Eigen::Vector3d& q) {
        return Eigen::Vector3d(q + pier_displacement(s, q, c.epoch, c.bending));
    };
    // Material points on the grazing west wall 0.1 m from its south end, on the head-on
    // south wall 10 mm below its top edge, and on the west wall 0.1 m from its north end:
    // each is seen at exactly its displaced position.
    for (const Eigen::Vector3d& q : {Eigen::Vector3d(s.pier.x0, s.pier.y0 + 0.1, 20.0),
                                     Eigen::Vector3d(9.5, s.pier.y0, s.pier.height - 0.01),
                                     Eigen::Vector3d(s.pier.x0, s.pier.y1 - 0.1, 30.0)}) {
        const Eigen::Vector3d p = displaced(q);
        const Hit h = cast_ray(scene, o, (p - o).normalized(), s.scanner.max_range);
        EXPECT_EQ(h.surface, Surface::pier) << q.transpose();
        if (h.surface != Surface::pier) continue;
        EXPECT_NEAR(h.range, (p - o).norm(), 1e-7) << q.transpose();
    }
    // 0.2 m beyond the displaced north end of the west wall there is only sky.
    const Eigen::Vector3d beyond =
        displaced(Eigen::Vector3d(s.pier.x0, s.pier.y1, 30.0)) + Eigen::Vector3d(0, 0.2, 0);
    const Hit h = cast_ray(scene, o, (beyond - o).normalized(), s.scanner.max_range);
    EXPECT_EQ(h.surface, Surface::none) << "range " << h.range;
}

// Noise statistics on the head-on south face, each error source alone, against the
// noise-free render of the same cells (n ≈ 35k points: the standardised mean is within
// 5/√n ≈ 0.03 of 0 and the standard deviation within 5/√(2n) ≈ 0.02 of 1).
//  - range noise: measured − true range ~ N(0, (a + b·r)²) along the readout ray;
//  - angular noise: the beam d(φ + ε_φ, e + ε_e) meets the plane y = y0 at range
//    r₀ (1 − cot φ · ε_φ + tan e · ε_e) to first order, and the point lies on the readout ray, so
//    (r − r₀)/r₀ ~ N(0, σ² (cot² φ + tan² e)): both angles must be perturbed.
TEST(SimulatorExact, RangeAndAngularNoiseHaveTheModelledSpread) {
    Site s = noise_free_small();
    const Scan free = render_epoch(s, 0, 0.0).scan;
    std::map<std::pair<std::uint32_t, std::uint32_t>, double> free_range;
    const Eigen::Vector3d o = s.scanner.position;
    for (std::size_t i = 0; i < free.size(); ++i) {
        const Eigen::Vector3d& p = free.xyz[i];
        if (p.z() < 1.0 || std::abs(p.y() - s.pier.y0) > 1e-6) continue;
        if (p.x() < s.pier.x0 + 0.5 || p.x() > s.pier.x1 - 0.5) continue;
        free_range[{free.grid->row[i], free.grid->column[i]}] = (p - o).norm();
    }
    for (const bool angular : {false, true}) {
        Site noisy = s;
        noisy.noise.enabled = true;
        noisy.noise.model = Noise::Model::constant;
        noisy.noise.angular_arcsec = angular ? 3.0 : 0.0;
        noisy.noise.range_a = angular ? 0.0 : 0.001;
        noisy.noise.range_b_ppm = angular ? 0.0 : 10.0;
        const Scan scan = render_epoch(noisy, 0, 0.0).scan;
        const double sa = 3.0 * kDeg / 3600.0;
        double n = 0, sum = 0, sum_sq = 0;
        for (std::size_t i = 0; i < scan.size(); ++i) {
            const auto it = free_range.find({scan.grid->row[i], scan.grid->column[i]});
            if (it == free_range.end()) continue;
            const double r0 = it->second, r = (scan.xyz[i] - o).norm();
            double sigma = 0.001 + 10e-6 * r0;
            if (angular) {
                const double az = cell_azimuth(s.scanner, scan.grid->column[i]);
                const double el = cell_elevation(s.scanner, scan.grid->row[i]);
                sigma = r0 * sa * std::hypot(1.0 / std::tan(az), std::tan(el));
            }
            const double z = (r - r0) / sigma;
            ++n;
            sum += z;
            sum_sq += z * z;
        }
        ASSERT_GT(n, 30'000);
        const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
        EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n)) << (angular ? "angular" : "range");
        EXPECT_NEAR(sd, 1.0, 5.0 / std::sqrt(2.0 * n)) << (angular ? "angular" : "range");
    }
}

// A sphere target's points are on the sphere around its true centre; after the knock
// event they are on the sphere around the moved centre (10 mm away).
TEST(SimulatorExact, SpherePointsFollowTheKnockedTarget) {
    Site s = noise_free_small();
    s.events.knocked_target = 0;  // T1, a sphere
    s.events.knocked_epoch = 3;
    s.events.knocked_displacement = {0.010, 0.0, 0.0};
    const Target& t = s.targets[0];
    ASSERT_EQ(t.kind, Target::Kind::sphere);
    for (const int epoch : {2, 3}) {
        const Eigen::Vector3d c = target_centre(s, 0, epoch);
        EXPECT_NEAR((c - t.centre).norm(), epoch >= 3 ? 0.010 : 0.0, 1e-12);
        const Scan scan = render_epoch(s, epoch, epoch * 0.25).scan;
        int on_sphere = 0;
        for (const auto& p : scan.xyz) {
            if ((p - t.centre).norm() > t.radius + 0.02) continue;
            EXPECT_NEAR((p - c).norm(), t.radius, 1e-9);
            ++on_sphere;
        }
        EXPECT_GE(on_sphere, 6) << "epoch " << epoch;  // r = 72.5 mm at 20 m, 0.1° steps
    }
}

// The step event moves one height band of the pier from its epoch on, and nothing else.
TEST(SimulatorExact, StepEventMovesOneBandFromItsEpoch) {
    Site s = noise_free_small();
    s.events.step_epoch = 2;
    s.events.step_z_min = 30.0;
    s.events.step_z_max = 40.0;
    s.events.step_displacement = {0.0, -0.010, 0.0};  // towards the scanner
    for (const int epoch : {1, 2}) {
        const Scan scan = render_epoch(s, epoch, epoch * 0.25).scan;
        std::size_t band = 0, below = 0;
        for (const auto& p : scan.xyz) {
            if (p.x() < s.pier.x0 + 0.5 || p.x() > s.pier.x1 - 0.5) continue;
            if (std::abs(p.y() - s.pier.y0) > 0.05 || p.z() < 1.0) continue;  // south face
            if (p.z() > 30.05 && p.z() < 39.95) {
                EXPECT_NEAR(p.y(), s.pier.y0 - (epoch >= 2 ? 0.010 : 0.0), 1e-9);
                ++band;
            } else if (p.z() < 29.95) {
                EXPECT_NEAR(p.y(), s.pier.y0, 1e-9);
                ++below;
            }
        }
        EXPECT_GT(band, 5'000u) << "epoch " << epoch;
        EXPECT_GT(below, 20'000u) << "epoch " << epoch;
    }
}

// Intensity = albedo(material point) · exp(−r / r_att) · |cos incidence| exactly (noise
// off), so it falls with range and incidence: the grazing west wall is far darker.
TEST(SimulatorExact, IntensityFollowsAlbedoRangeAndIncidence) {
    const Site s = noise_free_small();
    const Scan scan = render_epoch(s, 0, 0.0).scan;
    const Eigen::Vector3d o = s.scanner.position;
    std::size_t south = 0, west = 0, ground = 0;
    double south_sum = 0.0, west_sum = 0.0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        const Eigen::Vector3d& p = scan.xyz[i];
        const Eigen::Vector3d d = p - o;
        const double r = d.norm();
        const double fall = std::exp(-r / s.texture.range_attenuation);
        if (std::abs(p.y() - s.pier.y0) < 1e-6 && p.z() > 0.1) {
            const double cos_i = std::abs(d.y()) / r;  // face normal (0, −1, 0)
            const double a = concrete_albedo(s.texture, 2, p.x(), p.z());
            ASSERT_NEAR(scan.intensity[i], a * fall * cos_i, 1e-6);
            south_sum += scan.intensity[i];
            ++south;
        } else if (std::abs(p.x() - s.pier.x0) < 1e-6 && p.z() > 0.1) {
            const double cos_i = std::abs(d.x()) / r;  // face normal (−1, 0, 0)
            const double a = concrete_albedo(s.texture, 0, p.y(), p.z());
            ASSERT_NEAR(scan.intensity[i], a * fall * cos_i, 1e-6);
            west_sum += scan.intensity[i];
            ++west;
        } else if (std::abs(p.z()) < 1e-6) {
            const double cos_i = std::abs(d.z()) / r;
            ASSERT_NEAR(scan.intensity[i],
                        terrain_albedo(s.texture, s.terrain, p.x(), p.y()) * fall * cos_i, 1e-6);
            ++ground;
        }
    }
    ASSERT_GT(south, 30'000u);
    ASSERT_GT(west, 100u);
    ASSERT_GT(ground, 5'000u);
    EXPECT_LT(west_sum / west, 0.2 * south_sum / south);
}

// The `round` preset's column at 0.1°: every pier point lies on the cylinder of radius 2 m
// about the axis through the foot's centre — upright in epoch 0, leaning (θx, θy) about
// the foot after the tilt event — and its material point stays inside 0..height.
TEST(SimulatorExact, RoundPierIsTheCylinderUprightAndTilted) {
    Site s = preset_round();
    s.noise.enabled = false;
    s.drift.enabled = false;
    s.deformation.enabled = false;
    s.atmosphere.enabled = false;
    s.beam.footprint = false;
    s.occlusion.occluders.clear();
    s.occlusion.vegetation.clear();
    s.scanner.azimuth_min_deg = 75.0;
    s.scanner.azimuth_max_deg = 83.0;
    s.scanner.azimuth_step_deg = s.scanner.elevation_step_deg = 0.1;
    s.events.tilt_epoch = 1;
    s.events.tilt_arcsec = {60.0, -30.0};
    const Eigen::Vector3d foot(s.pier.centre().x(), s.pier.centre().y(), 0.0);
    for (const int epoch : {0, 1}) {
        const RenderedScan r = render_epoch(s, epoch, 0.25 * epoch);
        const Eigen::Vector2d t = pier_tilt(s, epoch);
        const Eigen::Vector3d axis = Eigen::Vector3d(t.x(), t.y(), 1.0).normalized();
        std::size_t on_pier = 0;
        for (std::size_t i = 0; i < r.scan.size(); ++i) {
            if (r.surface[i] != static_cast<std::uint8_t>(Surface::pier)) continue;
            const Eigen::Vector3d v = r.scan.xyz[i] - foot;
            const double radial = (v - axis * axis.dot(v)).norm();
            // First order in the tilt (3e-4 rad): the rotation's square is ~1e-7 m.
            ASSERT_NEAR(radial, 2.0, 1e-6) << "epoch " << epoch << " point " << i;
            ASSERT_GE(v.z(), -1e-3);
            ASSERT_LE(v.z(), s.pier.height + 1e-3);
            ++on_pier;
        }
        EXPECT_GT(on_pier, 15'000u) << "epoch " << epoch;
        if (epoch == 1) {
            // Leaning: against the upright axis the radial distance grows with the height.
            std::size_t off = 0;
            for (std::size_t i = 0; i < r.scan.size(); ++i) {
                if (r.surface[i] != static_cast<std::uint8_t>(Surface::pier)) continue;
                const Eigen::Vector3d v = r.scan.xyz[i] - foot;
                off += std::abs(std::hypot(v.x(), v.y()) - 2.0) > 2e-3 && v.z() > 20.0;
            }
            EXPECT_GT(off, 1000u);
        }
    }
}

}  // namespace
}  // namespace tlsmon::sim
