// The scene around the pier: terrain seen at long range, stable blocks, target masts and
// stands, occluders and vegetation, and what the truth says about them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <numbers>

#include "core/error.hpp"
#include "simulator/occluders.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/render.hpp"
#include "simulator/scene_file.hpp"
#include "simulator/series.hpp"
#include "simulator/target_layout.hpp"
#include "simulator/terrain.hpp"

namespace tlsmon::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::int64_t kStart = 1780293600;  // 2026-06-01T06:00:00Z

Surface surface_of(const RenderedScan& r, std::size_t i) {
    return static_cast<Surface>(r.surface[i]);
}

// Exact geometry: no noise, no drift, no deformation, one thin ray per cell.
Site exact(Site s) {
    s.noise.enabled = false;
    s.drift.enabled = false;
    s.deformation.enabled = false;
    s.beam.footprint = false;
    s.atmosphere.enabled = false;  // ranges unscaled by the air's refractive index
    return s;
}

// Distance of p from the box's surface (0 on a face).
double off_box(const Block& b, const Eigen::Vector3d& p) {
    const Eigen::Vector3d outside = (b.lo - p).cwiseMax(p - b.hi).cwiseMax(0.0);
    if (outside.norm() > 0.0) return outside.norm();
    return std::min((p - b.lo).minCoeff(), (b.hi - p).minCoeff());
}

// A profile piece: the analytic height on a slope and the level ends.
TEST(SimulatorScene, TerrainProfileIsPiecewiseLinearAndRaysMeetIt) {
    Terrain t;
    t.profile_y = {0.0, 60.0, 230.0, 320.0};
    t.profile_z = {20.0, 0.0, 0.0, 45.0};
    EXPECT_DOUBLE_EQ(terrain_height(t, -5.0), 20.0);
    EXPECT_DOUBLE_EQ(terrain_height(t, 30.0), 10.0);
    EXPECT_DOUBLE_EQ(terrain_height(t, 275.0), 22.5);
    EXPECT_DOUBLE_EQ(terrain_height(t, 400.0), 45.0);
    // From (0, 0, 21.5) down at 12°: crosses the floor z = 0 at y = 21.5 / tan 12°.
    const Eigen::Vector3d o(0.0, 0.0, 21.5);
    const Eigen::Vector3d d(0.0, std::cos(12 * kDeg), -std::sin(12 * kDeg));
    Eigen::Vector3d n;
    const double r = intersect_terrain(t, o, d, 1000.0, n);
    EXPECT_NEAR((o + r * d).y(), 21.5 / std::tan(12 * kDeg), 1e-9);
    EXPECT_NEAR((o + r * d).z(), 0.0, 1e-9);
    EXPECT_NEAR(n.z(), 1.0, 1e-12);
    // Level, the ray meets the north side where h = 21.5: y = 230 + 21.5 · 2.
    const double r2 = intersect_terrain(t, o, Eigen::Vector3d::UnitY(), 1000.0, n);
    EXPECT_NEAR(r2, 230.0 + 21.5 * 2.0, 1e-9);
    EXPECT_NEAR(n.y(), -45.0 / 90.0 / std::hypot(1.0, 0.5), 1e-12);
}

// Rough ground: each hit lies on the smooth slope raised along its normal by a height within
// ±roughness, that height the same wherever a ray meets that spot; the heights vary over a
// wavelength; without roughness the smooth slope.
TEST(SimulatorScene, RoughGroundIsTheSlopeRaisedAlongItsNormal) {
    Terrain t;
    t.profile_y = {60.0, 130.0};
    t.profile_z = {0.0, 25.0};
    const Eigen::Vector3d o(0.0, 0.0, 1.5);
    std::vector<double> heights;
    for (int k = 0; k < 200; ++k) {
        const Eigen::Vector3d d =
            (Eigen::Vector3d(0.013 * k - 1.3, 80.0, 7.0 + 0.011 * k) - o).normalized();
        Eigen::Vector3d n;
        t.roughness = 0.0;
        const double smooth = intersect_terrain(t, o, d, 1000.0, n);
        t.roughness = 0.01;
        Eigen::Vector3d n_rough;
        const double rough = intersect_terrain(t, o, d, 1000.0, n_rough);
        const Eigen::Vector3d p = o + rough * d;
        // Its height above the smooth slope, along the slope's normal.
        const double h = n.dot(p - (o + smooth * d));
        EXPECT_LE(std::abs(h), 0.01 + 1e-9) << k;
        heights.push_back(h);
        // The same spot met from elsewhere has the same height.
        const Eigen::Vector3d o2(3.0, 10.0, 4.0);
        Eigen::Vector3d n2;
        const double again = intersect_terrain(t, o2, (p - o2).normalized(), 1000.0, n2);
        EXPECT_NEAR(((o2 + again * (p - o2).normalized()) - p).norm(), 0.0, 2e-4) << k;
    }
    double lo = 1, hi = -1;
    for (double h : heights) lo = std::min(lo, h), hi = std::max(hi, h);
    EXPECT_GT(hi - lo, 0.008);  // the ground is rough, not a shifted plane
    t.roughness = -0.01;
    EXPECT_THROW(validate_terrain(t), Error);
    // A scene file sets it.
    const Site s = parse_scene_file(
        "preset = \"small\"\n[terrain]\nroughness = 0.02\nroughness_wavelength = 0.5\n",
        "scene.toml", std::nullopt);
    EXPECT_EQ(s.terrain.roughness, 0.02);
    EXPECT_EQ(s.terrain.roughness_wavelength, 0.5);
}

// Rough ground seen at a grazing angle hides what lies behind its bumps: every spot of a
// slope roughened by ±3 cm at 0.1 m (its flanks up to some 40° steep) is met by a ray along
// the slope's normal; seen 80° off the normal from 80 m a share of them is hidden, the ray
// stopping on the ground in front of the spot; and every hit lies on the ground, where a ray
// along the normal meets it too.
TEST(SimulatorScene, RoughGroundShadowsWhatLiesBehindItsBumps) {
    Terrain t;
    t.profile_y = {60.0, 130.0};
    t.profile_z = {0.0, 25.0};
    t.roughness = 0.03;
    t.roughness_wavelength = 0.1;
    const Eigen::Vector3d n = Eigen::Vector3d(0.0, -25.0 / 70.0, 1.0).normalized();
    const double kDeg = 3.141592653589793 / 180.0;
    // Down the slope, 80° off its normal.
    const Eigen::Vector3d grazing =
        (std::cos(80 * kDeg) * n + std::sin(80 * kDeg) * Eigen::Vector3d::UnitX().cross(n))
            .normalized();
    ASSERT_LT(grazing.y(), 0.0);
    // The ground where a ray along the normal through (x, y on the smooth slope) meets it.
    const auto spot = [&](const Eigen::Vector3d& q) {
        Eigen::Vector3d m;
        const Eigen::Vector3d from = q + 10.0 * n;
        return Eigen::Vector3d(from - intersect_terrain(t, from, -n, 100.0, m) * n);
    };
    int spots = 0, hidden = 0, grazed = 0;
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 40; ++j) {
            const double y = 80.0 + 0.0113 * j;
            const Eigen::Vector3d q(0.0127 * i, y, terrain_height(t, y));
            const Eigen::Vector3d p = spot(q);
            ASSERT_LE(std::abs(n.dot(p - q)), 0.03 + 1e-9);
            ++spots;
            // Seen along its normal from 30 m: the spot itself.
            Eigen::Vector3d m;
            const Eigen::Vector3d above = p + 30.0 * n;
            EXPECT_NEAR(intersect_terrain(t, above, -n, 100.0, m), 30.0, 1e-5);
            // Seen from 80 m at 80°: the spot, or ground in front of it.
            const Eigen::Vector3d o = p + 80.0 * grazing;
            const double r = intersect_terrain(t, o, -grazing, 200.0, m);
            // A ray that dips into a crest for less than a step (wavelength/16) passes it.
            grazed += r > 80.0 + 1e-5;
            const Eigen::Vector3d hit = o - r * grazing;
            EXPECT_NEAR((spot(hit) - hit).norm(), 0.0, 1e-5) << i << " " << j;
            hidden += r < 80.0 - 1e-3;
        }
    EXPECT_GT(hidden, spots / 20);
    EXPECT_LT(hidden, spots * 3 / 4);
    EXPECT_LE(grazed, spots / 200);
    std::printf("rough ground at 80 deg: %d of %d spots hidden, %d passed by\n", hidden, spots,
                grazed);
}

// hochmosel: the valley floor is seen beyond 150 m (down to the dark patches of the
// ground), around the pier's foot, and the pier's foundation and the abutment are seen.
TEST(SimulatorScene, HochmoselSeesTheGroundBeyond150mAndThePierFoot) {
    Site s = preset_hochmosel();
    s.scanner.azimuth_step_deg = 0.1;  // the preset's geometry on a coarser grid
    s.scanner.elevation_step_deg = 0.1;
    s.occlusion.occluders.clear();
    const RenderedScan r = render_epoch(s, 0, 0.0, 2);
    const Eigen::Vector3d o = s.scanner.position;
    const Pier& p = s.pier;
    std::size_t beyond150 = 0, dark_far = 0, near_foot = 0, foundation = 0, abutment = 0;
    // Footprints up to 6 cm wide straddle edges (mixed pixels, labelled by the surface
    // returning most power) and the drift tilts the frame by a few mm at 170 m: nearly all
    // points, not every one, lie within 5 cm of their surface.
    std::size_t labelled = 0, on_surface = 0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        const Eigen::Vector3d& q = r.scan.xyz[i];
        const double horizontal = (q - o).head<2>().norm();
        switch (surface_of(r, i)) {
            case Surface::ground: {
                ++labelled;
                on_surface += std::abs(q.z() - terrain_height(s.terrain, q.y())) < 0.05;
                if (horizontal > 150.0) ++beyond150;
                if (horizontal > 170.0 && terrain_albedo(s.texture, s.terrain, q.x(), q.y()) < 0.15)
                    ++dark_far;
                // Within 15 m of the pier's footprint.
                const double dx = std::max({p.x0 - q.x(), q.x() - p.x1, 0.0});
                const double dy = std::max({p.y0 - q.y(), q.y() - p.y1, 0.0});
                if (std::hypot(dx, dy) < 15.0) ++near_foot;
                break;
            }
            case Surface::foundation:
                ++labelled;
                on_surface += off_box(s.terrain.blocks[0], q) < 0.05;
                ++foundation;
                break;
            case Surface::abutment:
                ++labelled;
                on_surface += off_box(s.terrain.blocks[1], q) < 0.05;
                ++abutment;
                break;
            default:
                break;
        }
    }
    std::cout << "hochmosel at 0.1°: " << beyond150 << " ground points beyond 150 m (" << dark_far
              << " on ground darker than 0.15 beyond 170 m), " << near_foot
              << " within 15 m of the pier's foot, " << foundation << " on the foundation, "
              << abutment << " on the abutment\n";
    EXPECT_GT(on_surface, labelled * 97 / 100);
    EXPECT_GT(beyond150, 20'000u);
    EXPECT_GT(dark_far, 1'000u);  // reflectance below 0.15 at over 170 m still returns
    EXPECT_GT(near_foot, 3'000u);
    EXPECT_GT(foundation, 800u);
    EXPECT_GT(abutment, 1'500u);
    EXPECT_EQ(r.points_by_surface[static_cast<int>(Surface::foundation)], foundation);
}

// small: every foundation and abutment point lies exactly on its block.
TEST(SimulatorScene, StableBlocksAreSeenWhereTheyStand) {
    const Site s = exact(preset_small());
    const RenderedScan r = render_epoch(s, 0, 0.0, 2);
    std::size_t n[2] = {0, 0};
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        const Surface k = surface_of(r, i);
        if (k != Surface::foundation && k != Surface::abutment) continue;
        const int b = k == Surface::foundation ? 0 : 1;
        EXPECT_LT(off_box(s.terrain.blocks[b], r.scan.xyz[i]), 1e-9);
        ++n[b];
    }
    EXPECT_GT(n[0], 500u);
    EXPECT_GT(n[1], 100u);
}

// A creeping patch of the slope (a scene file's terrain.creep_*): from its first epoch on,
// the ground inside its circle is the unmoved profile shifted by rate·(epoch − from + 1),
// outside it is unmoved, and the truth says how far it has gone.
TEST(SimulatorScene, ACreepingPatchMovesTheGroundInsideItsCircleOnly) {
    Site s = exact(parse_scene_file(R"(preset = "small"
[terrain]
creep_from_epoch = 1
creep_centre = [-3.0, 75.0]
creep_radius = 4.0
creep_rate_m = [0.0, -0.003, -0.002]
)",
                                    "scene.toml", std::nullopt));
    const Eigen::Vector3d v = 3.0 * Eigen::Vector3d(0.0, -0.003, -0.002);
    EXPECT_TRUE(s.terrain.creep.displacement(0).isZero());
    EXPECT_TRUE(s.terrain.creep.displacement(3).isApprox(v));
    const RenderedScan r = render_epoch(s, 3, 6.0, 2);
    int inside = 0, outside = 0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        if (surface_of(r, i) != Surface::ground) continue;
        const Eigen::Vector3d& p = r.scan.xyz[i];
        const double d = (Eigen::Vector2d(p.x(), p.y()) - s.terrain.creep.centre).norm();
        if (d < 3.9) {
            EXPECT_NEAR(p.z() - v.z(), terrain_height(s.terrain, p.y() - v.y()), 1e-9) << i;
            ++inside;
        } else if (d > 4.1) {
            EXPECT_NEAR(p.z(), terrain_height(s.terrain, p.y()), 1e-9) << i;
            ++outside;
        }
    }
    EXPECT_GT(inside, 50);
    EXPECT_GT(outside, 1000);
    const EpochFiles f = simulate_epoch(s, 3, kStart, 2);
    const auto& creep = f.truth["terrain"]["creep"];
    EXPECT_EQ(creep["from_epoch"].get<int>(), 1);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(creep["displacement_m"][k].get<double>(), v(k), 1e-15);
}

// T1 of `small` is a sphere on a mast 20 m out at azimuth 92°, 1.0 m above the ground: its
// mast is hit below the sphere, on the mast's surface, and the sphere's points and the
// truth's centre are those of the sphere alone.
TEST(SimulatorScene, MastIsHitBelowItsSphereAndTheCentreIsUnchanged) {
    const Site s = exact(preset_small());
    const Target& t = s.targets[0];
    ASSERT_EQ(t.kind, Target::Kind::sphere);
    ASSERT_EQ(t.mount, Target::Mount::mast);
    const Eigen::Vector3d c(20.0 * std::cos(92 * kDeg), 20.0 * std::sin(92 * kDeg), 1.0);
    EXPECT_LT((t.centre - c).norm(), 1e-12);
    const EpochFiles f = simulate_epoch(s, 0, kStart, 2);
    const auto& centre = f.truth["targets"][0]["centre"];
    EXPECT_NEAR(centre[0].get<double>(), c.x(), 1e-12);
    EXPECT_NEAR(centre[1].get<double>(), c.y(), 1e-12);
    EXPECT_NEAR(centre[2].get<double>(), c.z(), 1e-12);
    EXPECT_EQ(f.truth["targets"][0]["mount"], "mast");

    const RenderedScan r = render_epoch(s, 0, 0.0, 2);
    std::size_t mast = 0, sphere = 0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
        const Eigen::Vector3d& q = r.scan.xyz[i];
        if ((q - c).head<2>().norm() > 0.2) continue;
        if (surface_of(r, i) == Surface::mast) {
            EXPECT_NEAR((q - c).head<2>().norm(), kMastRadius, 1e-9);
            EXPECT_LT(q.z(), c.z() - 0.9 * t.radius);
            EXPECT_GE(q.z(), 0.0);
            ++mast;
        } else if (surface_of(r, i) == Surface::sphere) {
            EXPECT_NEAR((q - c).norm(), t.radius, 1e-9);
            ++sphere;
        }
    }
    EXPECT_GE(mast, 10u);  // 1 m of mast at 20 m and 0.1°: ≈ 28 rows
    EXPECT_GE(sphere, 6u);
}

// In an epoch without occluders every target of every preset is the first surface met by
// the ray from the station to its centre (and to eight points around it).
TEST(SimulatorScene, EveryPresetTargetIsVisibleFromTheStation) {
    for (const std::string& name : preset_names()) {
        const Site s = preset(name);
        ASSERT_GE(s.targets.size(), 4u) << name;
        int spheres = 0, boards = 0;
        int epoch = 0;
        for (;; ++epoch) {
            bool any = false;
            for (const OccluderState& st : occluder_states(s, epoch)) any |= st.present;
            if (!any) break;
        }
        const SceneAtEpoch scene(s, epoch, 0.0);
        for (std::size_t i = 0; i < s.targets.size(); ++i) {
            const Target& t = s.targets[i];
            (t.kind == Target::Kind::sphere ? spheres : boards)++;
            const Eigen::Vector3d o = s.scanner.position;
            const Hit h = cast_ray(scene, o, (t.centre - o).normalized(), s.scanner.max_range);
            EXPECT_EQ(h.target, static_cast<int>(i)) << name << " " << t.name;
            EXPECT_TRUE(h.surface == Surface::sphere || h.surface == Surface::checkerboard)
                << name << " " << t.name << " hit " << surface_name(h.surface);
            // Inside the scan window.
            const Eigen::Vector3d v = t.centre - o;
            const double az = std::atan2(v.y(), v.x()) / kDeg - s.scanner.heading_deg;
            const double el = std::atan2(v.z(), v.head<2>().norm()) / kDeg;
            EXPECT_GT(az, s.scanner.azimuth_min_deg) << name << " " << t.name;
            EXPECT_LT(az, s.scanner.azimuth_max_deg) << name << " " << t.name;
            EXPECT_GT(el, s.scanner.elevation_min_deg) << name << " " << t.name;
            EXPECT_LT(el, s.scanner.elevation_max_deg) << name << " " << t.name;
        }
        EXPECT_GE(spheres, 2) << name;
        EXPECT_GE(boards, 2) << name;
    }
}

// A van parked in front of the pier hides part of it: fewer pier points than in the same
// epoch without it, the van's own points, and the truth says where it stood.
TEST(SimulatorScene, OccluderEpochHidesPartOfThePierAndTheTruthSaysSo) {
    Site s = preset_small();
    s.occlusion = preset_pier().occlusion;
    s.occlusion.vegetation.clear();
    s.occlusion.occluders[0].probability = 0.0;  // the person stays away
    Occluder& van = s.occlusion.occluders[1];
    ASSERT_EQ(van.kind, Occluder::Kind::vehicle);
    van.probability = 1.0;
    // An epoch where the van stands in front of the pier's south face (x 2–17 seen at 33 m
    // is x 1.5–12.5 there).
    int epoch = 0;
    for (;; ++epoch) {
        const OccluderState st = occluder_states(s, epoch)[1];
        if (st.base.x() > 3.0 && st.base.x() < 10.0) break;
    }
    Site clear = s;
    clear.occlusion.occluders[1].probability = 0.0;
    const double hours = epoch * s.cadence_seconds / 3600.0;
    const RenderedScan with = render_epoch(s, epoch, hours, 2);
    const RenderedScan without = render_epoch(clear, epoch, hours, 2);
    const auto count = [](const RenderedScan& r, Surface k) {
        return r.points_by_surface[static_cast<int>(k)];
    };
    EXPECT_GT(count(with, Surface::occluder), 1'000u);
    EXPECT_EQ(count(without, Surface::occluder), 0u);
    EXPECT_LT(count(with, Surface::pier) + 500, count(without, Surface::pier));

    const EpochFiles f = simulate_epoch(s, epoch, kStart, 2);
    const auto& oj = f.truth["occlusion"]["occluders"][1];
    EXPECT_EQ(oj["name"], "van");
    EXPECT_TRUE(oj["present"].get<bool>());
    const OccluderState st = occluder_states(s, epoch)[1];
    EXPECT_NEAR(oj["position"][0].get<double>(), st.base.x(), 1e-12);
    EXPECT_NEAR(oj["position"][1].get<double>(), 33.0, 1e-12);
    EXPECT_FALSE(f.truth["occlusion"]["occluders"][0]["present"].get<bool>());
    EXPECT_EQ(f.truth["scan"]["points_by_surface"]["occluder"].get<std::uint64_t>(),
              count(with, Surface::occluder));
    // The truth's per-target flags agree with a ray cast to each target.
    const SceneAtEpoch scene(s, epoch, hours);
    for (std::size_t i = 0; i < s.targets.size(); ++i) {
        const Eigen::Vector3d o = s.scanner.position;
        const Hit h =
            cast_ray(scene, o, (s.targets[i].centre - o).normalized(), s.scanner.max_range);
        if (h.surface == Surface::occluder) {
            EXPECT_TRUE(f.truth["targets"][i]["occluded"].get<bool>()) << s.targets[i].name;
        }
    }
}

// The bush's points move between epochs (its leaves sway); the ground seen through and
// around it does not.
TEST(SimulatorScene, VegetationJittersBetweenEpochsWhileTheGroundStays) {
    Site s = exact(preset_small());
    s.occlusion.vegetation = preset_pier().occlusion.vegetation;
    s.occlusion.vegetation[0].centre = {8.0, 20.0};  // in front of the station, on the floor
    const Vegetation& v = s.occlusion.vegetation[0];
    const RenderedScan a = render_epoch(s, 3, 0.75, 2);
    const RenderedScan b = render_epoch(s, 4, 1.0, 2);
    using Cell = std::pair<std::uint32_t, std::uint32_t>;
    std::map<Cell, std::pair<Surface, Eigen::Vector3d>> first;
    for (std::size_t i = 0; i < a.scan.size(); ++i) {
        first[{a.scan.grid->row[i], a.scan.grid->column[i]}] = {surface_of(a, i), a.scan.xyz[i]};
    }
    std::size_t leaves = 0, moved = 0, ground = 0;
    for (std::size_t i = 0; i < b.scan.size(); ++i) {
        const auto it = first.find({b.scan.grid->row[i], b.scan.grid->column[i]});
        if (it == first.end()) continue;
        const Eigen::Vector3d& q = b.scan.xyz[i];
        if ((q.head<2>() - v.centre).norm() > v.radii.head<2>().maxCoeff() + 3.0) continue;
        const Surface k = surface_of(b, i);
        if (k == Surface::vegetation && it->second.first == Surface::vegetation) {
            ++leaves;
            if ((q - it->second.second).norm() > 1e-6) ++moved;
        } else if (k == Surface::ground && it->second.first == Surface::ground) {
            EXPECT_LT((q - it->second.second).norm(), 1e-9);
            EXPECT_NEAR(q.z(), 0.0, 1e-9);
            ++ground;
        }
    }
    EXPECT_GT(leaves, 200u);
    EXPECT_GT(moved, leaves * 9 / 10);
    EXPECT_GT(ground, 200u);
}

// Occluders and vegetation keep the render independent of the thread count.
TEST(SimulatorScene, OccludedRenderIsTheSameOnOneAndTwoThreads) {
    Site s = preset_small();
    s.occlusion = preset_pier().occlusion;
    for (Occluder& o : s.occlusion.occluders) o.probability = 1.0;
    const EpochFiles a = simulate_epoch(s, 2, kStart, 1);
    const EpochFiles b = simulate_epoch(s, 2, kStart, 2);
    EXPECT_TRUE(a.ptx == b.ptx);
    EXPECT_EQ(a.truth.dump(), b.truth.dump());
    EXPECT_GT(a.truth["scan"]["points_by_surface"]["vegetation"].get<int>(), 50);
}

// A scene file sets targets out by kind, distance or range, azimuth, height and mount.
TEST(SimulatorScene, SceneFilePlacesTargetsByDistanceAzimuthHeightAndMount) {
    const Site s = parse_scene_file(R"(preset = "small"
[terrain]
profile_y = [0.0, 100.0]
profile_z = [0.0, 10.0]
[[block]]
name = "F"
lo = [-2.0, 28.0, -1.0]
hi = [2.0, 32.0, 3.5]
[[target]]
name = "A"
distance = 20.0
azimuth_deg = 90.0
height = 1.5
mount = "mast"
[[target]]
name = "B"
kind = "checkerboard"
range = 40.0
azimuth_deg = 70.0
height = 1.2
mount = "stand"
size = 0.5
[[target]]
name = "C"
distance = 30.0
azimuth_deg = 90.0
height = 0.5
mount = "abutment"
radius = 0.1
[[target]]
name = "D"
centre = [5.0, 10.0, 4.0]
[[vegetation]]
name = "V"
centre = [3.0, 15.0]
[[occluder]]
name = "car"
kind = "vehicle"
probability = 0.5
path_start = [0.0, 10.0]
path_end = [10.0, 10.0]
)",
                                    "scene.toml", std::nullopt);
    ASSERT_EQ(s.targets.size(), 4u);
    // A: (0, 20) on the slope z = y/10 = 2, 1.5 m above it.
    EXPECT_NEAR(s.targets[0].centre.x(), 0.0, 1e-12);
    EXPECT_NEAR(s.targets[0].centre.y(), 20.0, 1e-12);
    EXPECT_NEAR(s.targets[0].centre.z(), 3.5, 1e-12);
    EXPECT_NEAR(s.targets[0].base_z, 2.0, 1e-12);
    // B: slant range 40 m from the station's centre (0, 0, 1.5).
    EXPECT_NEAR((s.targets[1].centre - s.scanner.position).norm(), 40.0, 1e-9);
    EXPECT_NEAR(s.targets[1].centre.z(), terrain_height(s.terrain, s.targets[1].centre.y()) + 1.2,
                1e-9);
    EXPECT_EQ(s.targets[1].mount, Target::Mount::stand);
    // C: on the block's top at 3.5 m.
    EXPECT_NEAR(s.targets[2].centre.z(), 4.0, 1e-12);
    EXPECT_DOUBLE_EQ(s.targets[2].radius, 0.1);
    EXPECT_EQ(s.targets[3].mount, Target::Mount::none);
    ASSERT_EQ(s.occlusion.occluders.size(), 1u);
    EXPECT_EQ(s.occlusion.occluders[0].kind, Occluder::Kind::vehicle);
    EXPECT_DOUBLE_EQ(s.occlusion.occluders[0].length, 5.0);
    ASSERT_EQ(s.occlusion.vegetation.size(), 1u);

    // An abutment mount with no block under it is an error naming the key and line.
    try {
        parse_scene_file(
            "[[target]]\nname = \"X\"\ndistance = 12.0\nazimuth_deg = 80.0\n"
            "mount = \"abutment\"\n",
            "bad.toml", std::nullopt);
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("bad.toml"), std::string::npos) << what;
        EXPECT_NE(what.find("no block"), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace tlsmon::sim
