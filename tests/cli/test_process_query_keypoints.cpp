// `tlsmon query keypoints`: the built binary on a database filled through the storage API —
// each zone's keypoint figures of an epoch on one row, an undefined zone with its counts
// only, the zone filter.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "pipeline/keypoint_results.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z

class QueryKeypoints : public ::testing::Test {
  protected:
    void SetUp() override {
        path_ = dir_ / "e.sqlite";
        auto db = EpochDatabase::open(path_, EpochDatabase::Mode::read_write);
        db.site().upsert_zone("south", "{}");
        db.site().upsert_zone("west", "{}");
        const auto id =
            db.epochs().insert({std::string(64, 'a'), kT0, "/ingest/s.ptx", 10, std::nullopt}).id;
        db.epochs().claim(id);
        EpochResults r;
        r.zone_results = {
            {"south", kKeypointCount, 140, std::nullopt, 180, false},
            {"south", kKeypointDx, -0.0012, 0.0003, 140, true},
            {"south", kKeypointAlongSurfaceH, -0.0012, 0.0003, 140, true},
            {"south", kKeypointAlongSurfaceV, 0.0004, 0.0005, 140, false},
            {"south", kKeypointHeight, 20.5, std::nullopt, 140, false},
            {"west", kKeypointCount, 3, std::nullopt, 7, false},
        };
        db.results().commit(id, r);
    }
    std::string db() const { return "--db " + path_.string(); }
    test::TempDir dir_;
    std::filesystem::path path_;
};

TEST_F(QueryKeypoints, OneRowPerZoneAndEpochWithItsFigures) {
    const auto r = test::run_tlsmon("query keypoints --format json " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto rows = nlohmann::json::parse(r.out);
    ASSERT_EQ(rows.size(), 2u) << r.out;
    EXPECT_EQ(rows[0]["zone"], "south");
    EXPECT_EQ(rows[0]["acquired"], "2026-03-01T12:00:00Z");
    EXPECT_EQ(rows[0]["matches"], 180);
    EXPECT_EQ(rows[0]["kept"], 140);
    EXPECT_DOUBLE_EQ(rows[0]["along_surface_h_m"].get<double>(), -0.0012);
    EXPECT_DOUBLE_EQ(rows[0]["lod95_v_m"].get<double>(), 0.0005);
    EXPECT_DOUBLE_EQ(rows[0]["height_m"].get<double>(), 20.5);
    EXPECT_TRUE(rows[0]["dy_m"].is_null());
    EXPECT_EQ(rows[1]["zone"], "west");
    EXPECT_EQ(rows[1]["kept"], 3);
    EXPECT_TRUE(rows[1]["dx_m"].is_null());

    const auto one = test::run_tlsmon("query keypoints --format json --zone west " + db());
    ASSERT_EQ(one.status, 0) << one.out;
    EXPECT_EQ(nlohmann::json::parse(one.out).size(), 1u);
}

}  // namespace
}  // namespace tlsmon
