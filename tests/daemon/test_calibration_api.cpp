// The calibration page's API (GET /api/v1/calibration): a check zone's M3C2 median scored
// against zero over the epochs of the window, with the reference epoch read as the datum but
// never scored, and the rest of the site's zones left unread.
#include <gtest/gtest.h>

#include "daemon/http/calibration_api.hpp"
#include "storage/epoch_database.hpp"
#include "tests/storage/fake_sha256.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kReference = 1'800'000'000;

// The reference epoch and ten more, 15 min apart. Check zone values (mm) with LoD95 1.96 mm,
// σ 1 mm: epochs 1–5 at 0.5 (within σ), 6–8 at 1.5 (within LoD95 only), 9–10 at 3 (outside).
// A moving zone beside it, never scored without a truth.
void commit_series(EpochDatabase& db) {
    db.site().upsert_zone("check",
                          R"({"type":"box","min":[0,0,0],"max":[1,1,1],"no_change":true})");
    db.site().upsert_zone("moving", R"({"type":"box","min":[0,0,2],"max":[1,1,3]})");
    for (int e = 0; e <= 10; ++e) {
        const EpochId id =
            db.epochs()
                .insert({test::fake_sha256(e + 1), kReference + 900 * e, "/i/s.ptx", 10, {}})
                .id;
        ASSERT_TRUE(db.epochs().claim(id));
        if (e == 0) db.epochs().set_reference(id);
        const double v = e == 0 ? 0.0 : e <= 5 ? 0.5e-3 : e <= 8 ? 1.5e-3 : 3e-3;
        EpochResults r;
        r.zone_results.push_back({"check", "m3c2_median_m", v, 1.96e-3, 50, false});
        r.zone_results.push_back({"moving", "m3c2_median_m", 0.01 * e, 1.96e-3, 50, true});
        db.results().commit(id, r);
    }
}

const Json& row(const Json& calibration, const std::string& method) {
    for (const Json& r : calibration.at("rows"))
        if (r.at("method") == method) return r;
    throw std::runtime_error("no row " + method + " in " + calibration.dump());
}

TEST(CalibrationApi, ScoresTheCheckZoneOverTheWindowWithTheReferenceAsDatumOnly) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
    commit_series(db);

    const Json all = calibration_json(db, {});
    EXPECT_EQ(all.at("epochs"), 11);
    EXPECT_TRUE(all.at("from").is_null());
    ASSERT_EQ(all.at("rows").size(), 1u) << "only the check zone: " << all.dump();
    const Json& r = row(all, "no_change:m3c2_median_m");
    EXPECT_EQ(r.at("part"), "check");
    EXPECT_EQ(r.at("n"), 10) << "the reference epoch is not scored";
    EXPECT_EQ(r.at("within68"), 5);
    EXPECT_EQ(r.at("within95"), 8);
    EXPECT_EQ(r.at("unit"), "m");
    EXPECT_NEAR(r.at("bias").get<double>(), (5 * 0.5e-3 + 3 * 1.5e-3 + 2 * 3e-3) / 10, 1e-12);
    EXPECT_NEAR(r.at("rms_sigma").get<double>(), 1e-3, 1e-12);
    EXPECT_EQ(r.at("verdict95"), "sigma too small");  // 8 of 10: band 49–94 %
    EXPECT_EQ(r.at("band95").size(), 2u);

    // From epoch 6 on: the reference lies outside the window, five epochs are scored.
    const Json later = calibration_json(db, {kReference + 6 * 900, {}});
    EXPECT_EQ(later.at("epochs"), 5);
    const Json& w = row(later, "no_change:m3c2_median_m");
    EXPECT_EQ(w.at("n"), 5);
    EXPECT_EQ(w.at("within68"), 0);
    EXPECT_EQ(w.at("within95"), 3);
    // A window before anything: nothing to score.
    EXPECT_TRUE(calibration_json(db, {{}, kReference - 1}).at("rows").empty());
}

}  // namespace
}  // namespace tlsmon
