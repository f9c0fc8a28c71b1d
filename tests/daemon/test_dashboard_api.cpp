// The dashboard API's keypoint model curve (GET /api/v1/series, "model"): the newest defined
// fit of d(t, z), evaluated at the zone's height over the window the fit observed, equals the
// displacement it was fitted to; none for a quantity without a model.
#include <gtest/gtest.h>

#include "daemon/http/dashboard_api.hpp"
#include "tests/support/keypoint_band_series.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

TEST(DashboardApi, TheSeriesCarriesTheKeypointModelAtTheZonesHeight) {
    // tests/support/keypoint_band_series.hpp: five bands at 2 … 18 m, twelve epochs, a
    // known d(t, z), t in hours since the reference.
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
    const UtcSeconds reference = 1'800'000'000;
    const auto truth = test::band_displacement;
    const auto zones = test::commit_keypoint_band_series(db, reference).zones;

    const Json series =
        series_json(db, series_view(db, {zones[2], kKeypointAlongSurfaceH, {}, 400}));
    const Json& model = series.at("model");
    ASSERT_TRUE(model.is_object()) << series.dump();
    EXPECT_DOUBLE_EQ(model.at("zone_height_m").get<double>(), 10.0);
    const Json& points = model.at("points");
    ASSERT_EQ(points.size(), 100u);  // a quarter of the width
    // From the first to the last hour the fit saw (0.25 h to 3 h), each on the truth.
    EXPECT_EQ(points.front()[0].get<std::int64_t>(), reference + 900);
    EXPECT_EQ(points.back()[0].get<std::int64_t>(), reference + 12 * 900);
    for (const auto& p : points) {
        const double t = double(p[0].get<std::int64_t>() - reference) / 3600.0;
        EXPECT_NEAR(p[1].get<double>(), truth(t, 10.0), 1e-9) << p.dump();
    }
    // A window inside the fit clips the curve; a quantity without a model has none.
    const Json later = series_json(
        db, series_view(db, {zones[2], kKeypointAlongSurfaceH, {reference + 7200, {}}, 40}));
    ASSERT_TRUE(later.at("model").is_object());
    EXPECT_EQ(later.at("model").at("points").front()[0].get<std::int64_t>(), reference + 7200);
    EXPECT_EQ(later.at("model").at("points").size(), 10u);
    EXPECT_TRUE(series_json(db, series_view(db, {zones[2], kKeypointHeight, {}, 400}))
                    .at("model")
                    .is_null());
    EXPECT_TRUE(series_json(db, series_view(db, {"no such zone", kKeypointAlongSurfaceH, {}, 4}))
                    .at("model")
                    .is_null());
}

// The epoch view's map: absent (404) for an epoch without one, the server's fault (500, not
// "absent") for one whose stored arrays do not fit together.
TEST(DashboardApi, ACorePointMapThatCannotBePutTogetherIsNotCalledAbsent) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
    const UtcSeconds reference = 1'800'000'000;
    const auto series = test::commit_keypoint_band_series(db, reference);
    bool absent = false;
    EXPECT_THROW(core_point_map_json(db, 999, absent), Error);
    EXPECT_TRUE(absent) << "no such epoch";
    EXPECT_THROW(core_point_map_json(db, series.last, absent), Error);
    EXPECT_TRUE(absent) << "an epoch without M3C2";

    const EpochId id =
        db.epochs().insert({test::fake_sha256(99), reference + 99 * 900, "/i/c.ptx", 10, {}}).id;
    ASSERT_TRUE(db.epochs().claim(id));
    EpochResults r;
    r.core_point_arrays = {{"m3c2_distance_m", {0.001f, 0.002f, 0.003f}},
                           {"m3c2_lod95_m", {0.001f, 0.001f}},  // one short
                           {"m3c2_n1", {10, 10, 10}},
                           {"m3c2_n2", {10, 10, 10}}};
    db.results().commit(id, r);
    try {
        core_point_map_json(db, id, absent);
        ADD_FAILURE() << "an inconsistent map was put together";
    } catch (const Error& e) {
        EXPECT_FALSE(absent);
        EXPECT_NE(std::string(e.what()).find("'m3c2_lod95_m' is missing or of another length"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace tlsmon
