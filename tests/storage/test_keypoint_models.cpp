// The keypoint displacement model's rows: stored with the epoch's commit and read back by
// time range and quantity, residuals included; incomplete, non-finite or rejected-epoch
// models refused with nothing of the epoch stored.
#include <gtest/gtest.h>

#include <cmath>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

struct Fixture {
    test::TempDir dir;
    EpochDatabase db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    EpochId claimed(int n, UtcSeconds t) {
        const auto id =
            db.epochs().insert({test::fake_sha256(n), t, "/ingest/s.ptx", 10, std::nullopt}).id;
        EXPECT_TRUE(db.epochs().claim(id));
        return id;
    }
};

KeypointModelRow defined_model(const std::string& quantity, double scale) {
    KeypointModelRow m;
    m.quantity = quantity;
    m.variable = "time_h";
    m.defined = true;
    m.observations = 520;
    m.iterations = 140;
    m.converged = true;
    m.t_centre = 3.125;
    m.t_scale = 3.125;
    m.z_centre = 20;
    m.z_scale = 19;
    m.coefficients = std::array<double, 10>{};
    for (int k = 0; k < 10; ++k) (*m.coefficients)[k] = scale * (k + 1) * 1e-4;
    m.sum_abs_residuals = 1.42;
    m.residual_scale = 0.00037;
    m.residuals = {{"keypoint_band_0_5", 6.25, 1.0, 0.0021, -0.0001},
                   {"keypoint_band_5_10", 6.25, 3.0, 0.0025, 0.0002}};
    return m;
}

TEST(KeypointModels, StoredWithTheEpochAndReadBackByRangeAndQuantity) {
    Fixture f;
    const auto first = f.claimed(1, 1000);
    EpochResults r;
    KeypointModelRow undefined;
    undefined.quantity = "keypoint_along_surface_h_m";
    undefined.variable = "time_h";
    undefined.observations = 20;
    undefined.reason = "the (t, z) points carry only 4 of the 10 terms";
    r.keypoint_models = {undefined};
    f.db.results().commit(first, r);

    const auto second = f.claimed(2, 2000);
    r.keypoint_models = {defined_model("keypoint_along_surface_h_m", 1.0),
                         defined_model("keypoint_dz_m", -2.0)};
    f.db.results().commit(second, r);

    const auto all = f.db.keypoint_models().in_range({});
    ASSERT_EQ(all.size(), 3u);
    EXPECT_EQ(all[0].epoch, first);
    EXPECT_EQ(all[0].acquired, 1000);
    EXPECT_FALSE(all[0].model.defined);
    EXPECT_EQ(all[0].model.reason, undefined.reason);
    EXPECT_EQ(all[0].model.observations, 20);
    EXPECT_FALSE(all[0].model.coefficients.has_value());
    EXPECT_FALSE(all[0].model.t_centre.has_value());
    EXPECT_TRUE(all[0].model.residuals.empty());
    // Same epoch: by quantity name.
    EXPECT_EQ(all[1].model.quantity, "keypoint_along_surface_h_m");
    EXPECT_EQ(all[2].model.quantity, "keypoint_dz_m");
    const auto& m = all[2].model;
    EXPECT_TRUE(m.defined && m.converged);
    EXPECT_EQ(m.iterations, 140);
    EXPECT_EQ(*m.t_centre, 3.125);
    EXPECT_EQ(*m.z_scale, 19);
    ASSERT_TRUE(m.coefficients.has_value());
    for (int k = 0; k < 10; ++k) EXPECT_EQ((*m.coefficients)[k], -2.0 * (k + 1) * 1e-4);
    EXPECT_EQ(*m.residual_scale, 0.00037);
    ASSERT_EQ(m.residuals.size(), 2u);
    EXPECT_EQ(m.residuals[1].zone, "keypoint_band_5_10");
    EXPECT_EQ(m.residuals[1].z, 3.0);
    EXPECT_EQ(m.residuals[1].residual, 0.0002);

    EXPECT_EQ(f.db.keypoint_models().in_range({}, "keypoint_dz_m").size(), 1u);
    EXPECT_EQ(f.db.keypoint_models().in_range({1500, std::nullopt}).size(), 2u);
    EXPECT_EQ(f.db.keypoint_models().in_range({std::nullopt, 1500}).size(), 1u);
    EXPECT_TRUE(f.db.keypoint_models().in_range({}, "m3c2_mean_m").empty());
}

TEST(KeypointModels, IncompleteOrNonFiniteModelsAreRefusedAndNothingIsStored) {
    Fixture f;
    const auto id = f.claimed(1, 1000);
    const auto refused = [&](const KeypointModelRow& m) {
        EpochResults r;
        r.keypoint_models = {m};
        EXPECT_THROW(f.db.results().commit(id, r), StorageError);
        EXPECT_EQ(f.db.epochs().find(id)->status, EpochStatus::processing);
    };
    auto m = defined_model("keypoint_dz_m", 1);
    m.coefficients.reset();
    refused(m);  // defined without coefficients
    m = defined_model("keypoint_dz_m", 1);
    (*m.coefficients)[3] = std::nan("");
    refused(m);
    m = defined_model("keypoint_dz_m", 1);
    m.residuals[0].residual = INFINITY;
    refused(m);
    m = defined_model("keypoint_dz_m", 1);
    m.defined = false;
    m.reason = "x";
    refused(m);  // undefined with figures
    m = KeypointModelRow{};
    m.quantity = "keypoint_dz_m";
    m.variable = "time_h";
    refused(m);  // undefined without a reason
    EXPECT_TRUE(f.db.keypoint_models().in_range({}).empty());

    // A rejected epoch has no analysis results, a model included.
    EpochResults rejected;
    rejected.outcome = EpochStatus::rejected;
    rejected.reason = "registration failed";
    rejected.keypoint_models = {defined_model("keypoint_dz_m", 1)};
    EXPECT_THROW(f.db.results().commit(id, rejected), StorageError);
}

}  // namespace
}  // namespace tlsmon
