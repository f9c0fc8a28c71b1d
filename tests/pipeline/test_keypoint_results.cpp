// What the keypoint stage stores: a segment's zone rows (values, LoD95, significance, the
// undefined figures left out), vertical-angle bands as zones, and the displacement model
// fitted over series read back from the database, committed and read back.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "pipeline/keypoint_results.hpp"
#include "tests/storage/fake_sha256.hpp"
#include "tests/support/keypoint_band_series.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

keypoints::SegmentDisplacement defined_segment() {
    keypoints::SegmentDisplacement s;
    s.segment = 18;
    s.matches = 60;
    s.count = 50;
    s.mean = {0.0010, -0.0002, 0.0030};
    s.std_dev = {0.001, 0.001, 0.002};
    s.standard_error = s.std_dev / std::sqrt(50.0);
    s.wall.centroid = {10, 20, 7.5};
    s.wall.normal = {0, -1, 0};
    s.wall.horizontal = {1, 0, 0};
    s.wall.vertical = {0, 0, 1};
    s.along = {0.0002, 0.0010, 0.0030};
    s.along_std_dev = {0.001, 0.001, 0.002};
    s.along_standard_error = s.along_std_dev / std::sqrt(50.0);
    return s;
}

const ZoneResult* row(const std::vector<ZoneResult>& rows, const std::string& quantity) {
    for (const auto& r : rows)
        if (r.quantity == quantity) return &r;
    return nullptr;
}

TEST(KeypointResults, ZoneRowsOfADefinedSegment) {
    // The registration's σ 0.3 mm in every direction.
    const auto rows = keypoint_zone_results("band", defined_segment(),
                                            0.0003 * 0.0003 * Eigen::Matrix3d::Identity());
    ASSERT_EQ(rows.size(), 8u);
    for (const auto& r : rows) EXPECT_EQ(r.zone, "band");
    const auto* count = row(rows, "keypoint_count");
    ASSERT_TRUE(count);
    EXPECT_EQ(count->value, 50);
    EXPECT_EQ(count->n, 60);
    EXPECT_FALSE(count->uncertainty);
    // dz = 3.0 mm, LoD95 = 1.96 √((2 mm / √50)² + (0.3 mm)²) = 0.808 mm: significant.
    const auto* dz = row(rows, "keypoint_dz_m");
    ASSERT_TRUE(dz);
    EXPECT_DOUBLE_EQ(dz->value, 0.0030);
    EXPECT_NEAR(*dz->uncertainty, 1.96 * std::hypot(0.002 / std::sqrt(50.0), 0.0003), 1e-15);
    EXPECT_NEAR(*dz->uncertainty, 0.000808, 1e-6);
    EXPECT_TRUE(dz->significant);
    EXPECT_EQ(dz->n, 50);
    // dy = −0.2 mm against 1.96 √((1 mm / √50)² + (0.3 mm)²) = 0.650 mm: not significant.
    const auto* dy = row(rows, "keypoint_dy_m");
    ASSERT_TRUE(dy);
    EXPECT_NEAR(*dy->uncertainty, 0.000650, 1e-6);
    EXPECT_FALSE(dy->significant);
    EXPECT_DOUBLE_EQ(row(rows, "keypoint_dx_m")->value, 0.0010);
    EXPECT_DOUBLE_EQ(row(rows, "keypoint_along_normal_m")->value, 0.0002);
    EXPECT_DOUBLE_EQ(row(rows, "keypoint_along_surface_h_m")->value, 0.0010);
    EXPECT_TRUE(row(rows, "keypoint_along_surface_h_m")->significant);  // > 0.650 mm
    EXPECT_DOUBLE_EQ(row(rows, "keypoint_along_surface_v_m")->value, 0.0030);
    EXPECT_DOUBLE_EQ(row(rows, "keypoint_height_m")->value, 7.5);
}

TEST(KeypointResults, TheRegistrationEntersAlongEachFiguresOwnDirection) {
    // A registration uncertain only in z (1 mm): dz and the vertical along the wall hold it,
    // dx, dy and the horizontal and normal along the wall only their standard errors.
    Eigen::Matrix3d only_z = Eigen::Matrix3d::Zero();
    only_z(2, 2) = 1e-6;
    const auto rows = keypoint_zone_results("wall", defined_segment(), only_z);
    const double se1 = 0.001 / std::sqrt(50.0), se2 = 0.002 / std::sqrt(50.0);
    EXPECT_NEAR(*row(rows, "keypoint_dx_m")->uncertainty, 1.96 * se1, 1e-15);
    EXPECT_NEAR(*row(rows, "keypoint_dy_m")->uncertainty, 1.96 * se1, 1e-15);
    EXPECT_NEAR(*row(rows, "keypoint_dz_m")->uncertainty, 1.96 * std::hypot(se2, 0.001), 1e-15);
    EXPECT_NEAR(*row(rows, "keypoint_along_normal_m")->uncertainty, 1.96 * se1, 1e-15);
    EXPECT_NEAR(*row(rows, "keypoint_along_surface_h_m")->uncertainty, 1.96 * se1, 1e-15);
    EXPECT_NEAR(*row(rows, "keypoint_along_surface_v_m")->uncertainty,
                1.96 * std::hypot(se2, 0.001), 1e-15);
    // A wall turned 30° about z: its horizontal takes cos² 30° of a variance in x alone, its
    // normal sin² 30°.
    auto turned = defined_segment();
    const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
    turned.wall.normal = {-s, -c, 0};
    turned.wall.horizontal = {c, -s, 0};
    Eigen::Matrix3d only_x = Eigen::Matrix3d::Zero();
    only_x(0, 0) = 1e-6;
    const auto turned_rows = keypoint_zone_results("wall", turned, only_x);
    EXPECT_NEAR(*row(turned_rows, "keypoint_along_surface_h_m")->uncertainty,
                1.96 * std::hypot(se1, 0.001 * c), 1e-15);
    EXPECT_NEAR(*row(turned_rows, "keypoint_along_normal_m")->uncertainty,
                1.96 * std::hypot(se1, 0.001 * s), 1e-15);
    EXPECT_NEAR(*row(turned_rows, "keypoint_along_surface_v_m")->uncertainty, 1.96 * se2, 1e-15);
}

TEST(KeypointResults, UndefinedFiguresAreLeftOutNotStoredAsNaN) {
    auto no_wall = defined_segment();
    no_wall.wall = keypoints::WallFrame{};
    no_wall.along = Eigen::Vector3d::Constant(std::nan(""));
    no_wall.along_standard_error = Eigen::Vector3d::Constant(std::nan(""));
    const auto rows = keypoint_zone_results("z", no_wall);
    ASSERT_EQ(rows.size(), 4u);  // count, dx, dy, dz
    EXPECT_FALSE(row(rows, "keypoint_along_normal_m"));
    EXPECT_FALSE(row(rows, "keypoint_height_m"));

    keypoints::SegmentDisplacement undefined;
    undefined.matches = 12;
    undefined.count = 7;
    undefined.undefined_reason = "7 matches kept of 12, fewer than min_matches 10";
    const auto only = keypoint_zone_results("z", undefined);
    ASSERT_EQ(only.size(), 1u);
    EXPECT_EQ(only[0].quantity, "keypoint_count");
    EXPECT_EQ(only[0].value, 7);
    EXPECT_EQ(only[0].n, 12);
}

TEST(KeypointResults, VerticalAngleBandsAsZones) {
    const double five = 5 * std::numbers::pi / 180;
    EXPECT_EQ(keypoint_band_zone(18, five), "keypoint_band_0_5");
    EXPECT_EQ(keypoint_band_zone(17, five), "keypoint_band_-5_0");
    EXPECT_EQ(keypoint_band_zone(0, five), "keypoint_band_-90_-85");
    EXPECT_EQ(keypoint_band_zone(1, 2.5 * std::numbers::pi / 180), "keypoint_band_-87.5_-85");
    EXPECT_EQ(nlohmann::json::parse(keypoint_band_zone_definition(20, five)),
              nlohmann::json::parse(R"({"vertical_angle_deg":[10,15]})"));
}

TEST(KeypointResults, TheModelOverTheStoredSeriesIsCommittedAndReadBack) {
    // tests/support/keypoint_band_series.hpp: five bands, twelve epochs, a known d(t, z).
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
    const UtcSeconds reference = 1'800'000'000;
    const auto truth = test::band_displacement;
    const auto series = test::commit_keypoint_band_series(db, reference);
    EXPECT_EQ(series.stored_inputs, 55u);  // 11 epochs × 5 zones stored before the last
    const EpochId last = series.last;
    const auto stored = db.keypoint_models().in_range({});
    ASSERT_EQ(stored.size(), 1u);
    const auto& m = stored[0].model;
    EXPECT_EQ(stored[0].epoch, last);
    EXPECT_EQ(m.observations, 60);
    EXPECT_EQ(m.variable, "time_h");
    ASSERT_EQ(m.residuals.size(), 5u);
    for (const auto& r : m.residuals) {
        EXPECT_NEAR(r.residual, 0, 1e-9);
        EXPECT_DOUBLE_EQ(r.t, 3.0);
    }
    // The stored coefficients evaluate to the truth: t from 0.25 to 3 h, z from 2 to 18 m.
    EXPECT_NEAR(*m.t_centre, 1.625, 1e-12);
    EXPECT_NEAR(*m.z_scale, 8, 1e-12);
    keypoints::DisplacementModel back;
    back.t_centre = *m.t_centre;
    back.t_scale = *m.t_scale;
    back.z_centre = *m.z_centre;
    back.z_scale = *m.z_scale;
    for (int k = 0; k < 10; ++k) back.coefficients[k] = (*m.coefficients)[k];
    EXPECT_NEAR(back(2.0, 10.0), truth(2.0, 10.0), 1e-10);
    // The stored row evaluates itself (for the dashboard) as the kernel does, everywhere.
    for (double t : {0.0, 0.7, 2.0, 3.5})
        for (double z : {1.0, 10.0, 19.0})
            EXPECT_NEAR(*m.at(t, z), back(t, z), 1e-15) << t << " " << z;
    const auto latest = db.keypoint_models().latest_defined(kKeypointAlongSurfaceH);
    ASSERT_TRUE(latest);
    EXPECT_EQ(latest->epoch, last);
    EXPECT_EQ(latest->model.residuals.size(), 5u);
    EXPECT_FALSE(db.keypoint_models().latest_defined(kKeypointAlongSurfaceV));
    KeypointModelRow undefined;
    EXPECT_FALSE(undefined.at(1.0, 1.0));
}

}  // namespace
}  // namespace tlsmon
