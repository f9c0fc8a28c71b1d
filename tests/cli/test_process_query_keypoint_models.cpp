// `tlsmon query keypoint-models`: the built binary on a database filled through the storage
// API — the stored coefficients, convergence and reasons printed back, by quantity and time,
// and the residuals with --residuals.
#include <gtest/gtest.h>

#include <array>
#include <nlohmann/json.hpp>

#include "storage/epoch_database.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z

class QueryKeypointModels : public ::testing::Test {
  protected:
    void SetUp() override {
        path_ = dir_ / "e.sqlite";
        auto db = EpochDatabase::open(path_, EpochDatabase::Mode::read_write);
        for (int i = 0; i < 2; ++i) {
            const auto id = db.epochs()
                                .insert({std::string(63, 'a') + std::to_string(i), kT0 + 900 * i,
                                         "/ingest/s.ptx", 10, std::nullopt})
                                .id;
            db.epochs().claim(id);
            EpochResults r;
            KeypointModelRow m;
            m.quantity = "keypoint_along_surface_h_m";
            m.variable = "time_h";
            if (i == 0) {
                m.observations = 20;
                m.reason = "the (t, z) points carry only 4 of the 10 terms";
            } else {
                m.defined = true;
                m.converged = true;
                m.observations = 40;
                m.iterations = 37;
                m.t_centre = 0.125;
                m.t_scale = 0.125;
                m.z_centre = 10;
                m.z_scale = 8;
                m.coefficients =
                    std::array<double, 10>{0.0015, 0.0004, -0.0002, 0, 0, 0, 0, 0, 0, 1.5e-5};
                m.sum_abs_residuals = 0.0021;
                m.residual_scale = 0.00031;
                m.residuals = {{"keypoint_band_0_5", 0.25, 2, 0.0019, 0.0001},
                               {"keypoint_band_5_10", 0.25, 6, 0.0017, -0.0003}};
            }
            r.keypoint_models = {m};
            db.results().commit(id, r);
        }
    }
    std::string db() const { return "--db " + path_.string(); }
    test::TempDir dir_;
    std::filesystem::path path_;
};

TEST_F(QueryKeypointModels, CoefficientsAndReasonsAsJson) {
    const auto r = test::run_tlsmon("query keypoint-models --format json " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto rows = nlohmann::json::parse(r.out);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0]["acquired"], "2026-03-01T12:00:00Z");
    EXPECT_EQ(rows[0]["defined"], false);
    EXPECT_EQ(rows[0]["reason"], "the (t, z) points carry only 4 of the 10 terms");
    EXPECT_TRUE(rows[0]["a00"].is_null());
    EXPECT_EQ(rows[1]["defined"], true);
    EXPECT_EQ(rows[1]["quantity"], "keypoint_along_surface_h_m");
    EXPECT_EQ(rows[1]["variable"], "time_h");
    EXPECT_EQ(rows[1]["iterations"], 37);
    EXPECT_DOUBLE_EQ(rows[1]["a00"].get<double>(), 0.0015);
    EXPECT_DOUBLE_EQ(rows[1]["a01"].get<double>(), -0.0002);
    EXPECT_DOUBLE_EQ(rows[1]["a03"].get<double>(), 1.5e-5);
    EXPECT_DOUBLE_EQ(rows[1]["z_scale"].get<double>(), 8);
    EXPECT_DOUBLE_EQ(rows[1]["residual_scale"].get<double>(), 0.00031);
}

TEST_F(QueryKeypointModels, ResidualsTimeRangeAndQuantity) {
    auto r = test::run_tlsmon("query keypoint-models --residuals --format csv " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("epoch,acquired,quantity,zone,t,z,d,residual\n"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(",keypoint_band_5_10,0.25,6,0.0017,-0.0003"), std::string::npos) << r.out;
    r = test::run_tlsmon("query keypoint-models --format json --from 2026-03-01T12:10:00Z " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out).size(), 1u);
    r = test::run_tlsmon("query keypoint-models --format json --quantity keypoint_dz_m " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out).size(), 0u);
}

}  // namespace
}  // namespace tlsmon
