// The M3C2 stage on constructed planes with known answers: the pipeline's zone rows and core
// point arrays of a plate lifted 4 mm (core points of a 2 m lattice on a 0.5 m grid sit at
// the cubes' centres, so each zone's count is known), the reference product reused after a
// restart, and the map of an epoch into the reference frame (range scales about both
// scanners and a rigid transformation) undone exactly by pulling the cylinders back.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/registration/registration_error.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline_site.hpp"

namespace tlsmon::test {
namespace {

// Core points of the 21 x 21 grid (0.5 m, x, y in 0..10) on cubes of 2 m: at 1, 3, 5, 7, 9
// (the cube's centre) and 10 (the only points of the cube 10..12) in x and y.
M3c2Config plate_config() {
    M3c2Config c = plate_m3c2_config();
    c.zones.push_back(box_zone("plate", {-0.1, -0.1, -1.0}, {10.1, 10.1, 1.0}));
    // x + y <= 10: 5 + 4 + 3 + 2 + 1 + 0 core points.
    c.zones.push_back(prism_zone("triangle", {{0, 0}, {10, 0}, {0, 10}}, -1.0, 1.0));
    for (auto& b : bands_of(c.zones[0], 0, 4.0, 0.0, 10.0)) c.zones.push_back(b);
    return c;
}

std::optional<SeriesPoint> row(const EpochDatabase& db, const std::string& zone,
                               const std::string& quantity, EpochId epoch) {
    for (const auto& p : db.series().points(zone, quantity, {})) {
        if (p.epoch == epoch) return p;
    }
    return std::nullopt;
}

TEST(M3c2Stage, PlateLiftedFourMillimetresGivesZoneRowsAndArrays) {
    PipelineSite site;
    site.config.m3c2 = plate_config();
    for (const auto& z : site.config.m3c2.zones) site.db->site().upsert_zone(z.name, "{}");
    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.004);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
        ASSERT_EQ(site.process(e1, cache), EpochOutcome::done);
    }
    const auto& db = *site.db;
    const std::map<std::string, int> cores = {{"plate", 36},
                                              {"triangle", 15},
                                              {"plate 0–4 m", 12},
                                              {"plate 4–8 m", 12},
                                              {"plate 8–10 m", 12}};
    for (const auto& [zone, n] : cores) {
        SCOPED_TRACE(zone);
        const auto valid = row(db, zone, "m3c2_valid_count", e1.id);
        ASSERT_TRUE(valid);
        EXPECT_EQ(valid->value, n);
        EXPECT_EQ(valid->n, n);
        const auto median = row(db, zone, "m3c2_median_m", e1.id);
        ASSERT_TRUE(median);
        EXPECT_NEAR(median->value, 0.004, 1e-9);
        // No noise: the LoD is 1.96 reg alone.
        ASSERT_TRUE(median->uncertainty);
        EXPECT_NEAR(*median->uncertainty, 1.96 * 0.001, 1e-12);
        EXPECT_TRUE(median->significant);
        EXPECT_NEAR(row(db, zone, "m3c2_mean_m", e1.id)->value, 0.004, 1e-9);
        EXPECT_NEAR(row(db, zone, "m3c2_spread_m", e1.id)->value, 0.0, 1e-9);
        EXPECT_NEAR(row(db, zone, "m3c2_lod95_median_m", e1.id)->value, 1.96e-3, 1e-12);
        EXPECT_EQ(row(db, zone, "m3c2_significant_share", e1.id)->value, 1.0);
        // The reference against itself: zero everywhere, nothing significant.
        EXPECT_EQ(row(db, zone, "m3c2_median_m", e0.id)->value, 0.0);
        EXPECT_EQ(row(db, zone, "m3c2_significant_share", e0.id)->value, 0.0);
    }
    const auto d = db.series().core_point_array(e1.id, "m3c2_distance_m");
    ASSERT_TRUE(d);
    ASSERT_EQ(d->values.size(), 36u);
    for (float v : d->values) EXPECT_NEAR(v, 0.004f, 1e-7f);
    const auto n1 = db.series().core_point_array(e1.id, "m3c2_n1");
    ASSERT_TRUE(n1);
    // A core point inside the plate: the grid points (i, j)·0.5 m with i² + j² <= 4.
    float most = 0;
    for (float v : n1->values) most = std::max(most, v);
    EXPECT_EQ(most, 13.0f);
    const auto stages = db.series().stages(e1.id);
    ASSERT_EQ(stages.size(), 3u);  // coverage, registration (its datum), m3c2
    EXPECT_EQ(stages[1].stage, "registration");
    EXPECT_EQ(stages[2].stage, "m3c2");
    EXPECT_EQ(stages[2].note,
              "36 of 36 core points with a distance; registration σ along the normal up to "
              "1.00 mm");
}

TEST(M3c2Stage, ReferenceProductIsReusedAfterARestart) {
    PipelineSite site;
    site.config.m3c2 = plate_config();
    for (const auto& z : site.config.m3c2.zones) site.db->site().upsert_zone(z.name, "{}");
    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, -0.003);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
        EXPECT_EQ(cache.counters().built, 2);  // coverage and m3c2
    }
    site.restart();
    ReferenceCache cache(*site.db);
    ASSERT_EQ(site.process(e1, cache), EpochOutcome::done);
    EXPECT_EQ(cache.counters().built, 0);
    EXPECT_EQ(cache.counters().from_database, 2);
    EXPECT_NEAR(row(*site.db, "triangle", "m3c2_median_m", e1.id)->value, -0.003, 1e-9);
}

// Points on z = 0 (x, y in 0..6 every 0.1 m) and the same lifted `dz`.
std::vector<Eigen::Vector3d> plane(double dz) {
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i <= 60; ++i) {
        for (int j = 0; j <= 60; ++j) p.emplace_back(0.1 * i, 0.1 * j, dz);
    }
    return p;
}

Scan scan_of(std::vector<Eigen::Vector3d> points, const Eigen::Vector3d& scanner) {
    Scan s;
    s.xyz = std::move(points);
    s.pose.translation() = scanner;
    return s;
}

TEST(M3c2Stage, RangeScalesAndRegistrationAreUndoneByThePulledBackCylinders) {
    M3c2Config c;
    c.core_spacing = 1.0;
    c.normal_radii = {0.35};
    c.cylinder_radius = 0.3;
    c.max_depth = 0.2;
    c.min_points = 5;
    c.orient_to_scanner = true;  // the scanner is above the plane: normals point up
    c.zones.push_back(box_zone("plane", {0.5, 0.5, -1}, {5.5, 5.5, 1}));
    const Eigen::Vector3d s_r(3, -20, 10), s_e(3.2, -19.9, 10.1);
    const M3c2Reference ref = prepare_m3c2_reference(c, {scan_of(plane(0.0), s_r)});
    ASSERT_GT(ref.reference.size(), 20u);

    // The epoch as its scanner would deliver it: the plane lifted 4 mm in the reference
    // frame, then taken back through each step of the map (docs/m3c2.md, "Pipeline stage").
    const double k_e = 1 + 40e-6, k_r = 1 - 25e-6;
    registration::RigidTransform T;
    T.rotation = Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.1, 0.2, 1).normalized()).matrix();
    T.translation = Eigen::Vector3d(0.8, -1.5, 0.3);
    // Translation only, σ 0.3, 0.4, 0.5 mm: σ along a normal n is √(nᵀ diag n).
    T.small_rotation_covariance.setZero();
    T.small_rotation_covariance.diagonal().segment<3>(3) = Eigen::Vector3d(0.09, 0.16, 0.25) * 1e-6;
    std::vector<Eigen::Vector3d> epoch_points;
    for (const auto& q : plane(0.004)) {
        const Eigen::Vector3d y = s_r + (q - s_r) / k_r;
        const Eigen::Vector3d x = T.rotation.transpose() * (y - T.translation);
        epoch_points.push_back(s_e + k_e * (x - s_e));
    }
    StageOutputs o;
    o.to_reference = T;
    o.range_scale = k_e;
    o.scanner = s_e;
    o.reference_range_scale = k_r;
    const M3c2Epoch e = measure_m3c2(c, ref, {scan_of(epoch_points, s_e)}, o);
    std::size_t valid = 0;
    for (std::size_t k = 0; k < e.distances.size(); ++k) {
        const auto& d = e.distances[k];
        if (!std::isfinite(d.distance)) continue;
        ++valid;
        EXPECT_NEAR(d.distance, 0.004, 1e-9) << "core point " << k;
        const Eigen::Vector3d& n = ref.reference.normals()[k];
        EXPECT_NEAR(n.z(), 1.0, 1e-9);
        EXPECT_NEAR(e.registration_sigma[k], 0.0005, 1e-9);  // n = z: σ_z
        EXPECT_NEAR(d.lod, 1.96 * 0.0005, 1e-8);             // no noise: the reg term alone
    }
    EXPECT_EQ(valid, ref.reference.size());
}

}  // namespace
}  // namespace tlsmon::test
