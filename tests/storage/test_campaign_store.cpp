// Campaign epochs in a real SQLite file: stored with their segments in one transaction, read
// back by sha256, id and time range with every figure and every empty one; a second copy of
// the same bytes, a non-finite figure or a malformed sha256 refused with nothing stored.
#include <gtest/gtest.h>

#include <cmath>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "storage/series_reader.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

CampaignRow campaign(int n, UtcSeconds acquired, EpochId reference) {
    CampaignRow r;
    r.sha256 = test::fake_sha256(n);
    r.instrument = "backpack";
    r.kind = "pls";
    r.file_path = "/archive/pls_" + std::to_string(n) + ".ply";
    r.file_size = 1000 + n;
    r.acquired = acquired;
    r.added = acquired + 60;
    r.reference_epoch = reference;
    r.points = 519110;
    r.ground_points = 120000;
    r.global = {1e-5, -2e-5, 3e-5, 0.004, -0.005, 0.006};
    r.global_pairs = 200000;
    r.global_rmse = 0.021;
    r.segments = 2;
    r.registered_segments = 1;
    r.test_statistic = 12.5;
    r.test_dof = 6;
    r.test_p = 0.052;
    r.segments_differ = false;
    r.c2c_mean = 0.016;
    r.c2c_sigma = 0.012;
    r.c2c_median = 0.013;
    r.c2c_p95 = 0.04;
    r.c2c_missing = 17;
    r.parameters_json = R"({"metric":"point-to-plane"})";
    r.seconds = 12.4;
    return r;
}

std::vector<CampaignSegmentRow> segments() {
    CampaignSegmentRow wall;
    wall.segment = 0;
    wall.kind = "vertical";
    wall.cluster = 3;
    wall.points = 41000;
    wall.voxels = 9000;
    wall.outcome = "registered";
    wall.reference_segment = 2;
    wall.reference_overlap = 0.93;
    wall.pairs = 40000;
    wall.rank = 4;
    wall.iterations = 7;
    wall.converged = true;
    wall.centroid = {10.0, 50.0, 12.5};
    wall.parameters = {std::nullopt, 2e-4, 3e-4, 0.011, std::nullopt, -0.002};
    wall.sigmas = {std::nullopt, 1e-5, 2e-5, 0.0004, std::nullopt, 0.0006};
    wall.cut_fraction = 0.04;
    wall.cut_bias = 0.0002;
    wall.rmse = 0.02;
    wall.test_statistic = 3.1;
    wall.test_dof = 4;
    wall.test_p = 0.54;
    wall.c2c_mean = 0.015;
    wall.c2c_sigma = 0.011;
    wall.c2c_median = 0.012;
    wall.c2c_p95 = 0.037;
    wall.c2c_max = 0.09;
    CampaignSegmentRow bush;  // too small: nothing but its size
    bush.segment = 1;
    bush.kind = "other";
    bush.cluster = 5;
    bush.points = 300;
    bush.voxels = 80;
    bush.outcome = "too small";
    bush.reference_overlap = 0.2;  // on no reference segment enough
    return {wall, bush};
}

TEST(CampaignStore, StoredWithItsSegmentsAndReadBackWhole) {
    const test::TempDir dir("campaign-store");
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto reference =
        db.epochs().insert({test::fake_sha256(900), 1000, "/ingest/r.ptx", 10, std::nullopt}).id;
    const CampaignId first = db.campaigns().add(campaign(1, 5000, reference), segments());
    CampaignRow untestable = campaign(2, 3000, reference);
    untestable.test_statistic.reset();
    untestable.test_dof.reset();
    untestable.test_p.reset();
    untestable.segments_differ.reset();
    untestable.c2c_p95.reset();
    const CampaignId second = db.campaigns().add(untestable, {});
    EXPECT_NE(first, second);

    const auto found = db.campaigns().find(test::fake_sha256(1));
    ASSERT_TRUE(found);
    EXPECT_EQ(found->id, first);
    EXPECT_EQ(found->instrument, "backpack");
    EXPECT_EQ(found->reference_epoch, reference);
    EXPECT_EQ(found->global[5], 0.006);
    EXPECT_EQ(found->global_rmse, 0.021);
    EXPECT_EQ(found->test_dof, 6);
    ASSERT_TRUE(found->segments_differ);
    EXPECT_FALSE(*found->segments_differ);
    EXPECT_EQ(found->c2c_missing, 17);
    EXPECT_EQ(found->parameters_json, R"({"metric":"point-to-plane"})");
    EXPECT_FALSE(db.campaigns().find(test::fake_sha256(3)));

    // By acquisition time, oldest first; the window's bounds inclusive.
    const auto all = db.campaigns().in_range({});
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].id, second);
    EXPECT_FALSE(all[0].segments_differ);
    EXPECT_FALSE(all[0].test_p);
    EXPECT_FALSE(all[0].c2c_p95);
    EXPECT_EQ(db.campaigns().in_range({5000, std::nullopt}).size(), 1u);
    EXPECT_EQ(db.campaigns().in_range({3001, 4999}).size(), 0u);

    const auto rows = db.campaigns().segments(first);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].kind, "vertical");
    EXPECT_FALSE(rows[0].parameters[0]);
    EXPECT_EQ(rows[0].parameters[3], 0.011);
    EXPECT_EQ(rows[0].sigmas[5], 0.0006);
    EXPECT_FALSE(rows[0].sigmas[4]);
    EXPECT_EQ(rows[0].centroid[2], 12.5);
    EXPECT_EQ(rows[0].test_dof, 4);
    EXPECT_EQ(rows[0].c2c_max, 0.09);
    EXPECT_TRUE(rows[0].converged);
    EXPECT_EQ(rows[0].reference_segment, 2);
    EXPECT_EQ(rows[0].reference_overlap, 0.93);
    EXPECT_EQ(rows[1].outcome, "too small");
    EXPECT_FALSE(rows[1].reference_segment);
    EXPECT_EQ(rows[1].reference_overlap, 0.2);
    EXPECT_FALSE(rows[1].rmse);
    EXPECT_FALSE(rows[1].test_dof);
    EXPECT_FALSE(rows[1].centroid[0]);
    EXPECT_TRUE(db.campaigns().segments(second).empty());
}

CampaignPoints points() {
    CampaignPoints p;
    p.origin = {100.0, -2000.0, 35.0};
    p.spacing = 0.05;
    p.arrays = {{"x_m", {0.5f, -1.25f, 3.0f}},
                {"y_m", {1.0f, 2.0f, -3.0f}},
                {"z_m", {0.0f, 0.1f, 0.2f}},
                {"segment", {-1.0f, 0.0f, 1.0f}},
                {"c2c_dx_m", {std::nanf(""), 0.001f, -0.002f}}};
    return p;
}

TEST(CampaignStore, ItsFrameAndItsPointsReadBackWhole) {
    const test::TempDir dir("campaign-store-points");
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto reference =
        db.epochs().insert({test::fake_sha256(900), 1000, "/ingest/r.ptx", 10, std::nullopt}).id;
    CampaignRow row = campaign(1, 5000, reference);
    row.coarse = "planes";
    row.coarse_planes = 14;
    row.frame =
        std::array<double, 16>{0.6, -0.8, 0, 12.5, 0.8, 0.6, 0, -40.25, 0, 0, 1, 0.75, 0, 0, 0, 1};
    const CampaignId id = db.campaigns().add(row, segments(), points());
    const CampaignId bare = db.campaigns().add(campaign(2, 6000, reference), {});

    const auto back = db.campaigns().get(id);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->coarse, "planes");
    EXPECT_EQ(back->coarse_planes, 14);
    ASSERT_TRUE(back->frame);
    EXPECT_EQ(*back->frame, *row.frame);
    const auto p = db.campaigns().points(id);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->origin[1], -2000.0);
    EXPECT_EQ(p->spacing, 0.05);
    ASSERT_EQ(p->size(), 3u);
    ASSERT_EQ(p->arrays.size(), 5u);
    EXPECT_EQ(p->arrays[0].quantity, "x_m");  // in the order stored
    ASSERT_TRUE(p->array("x_m"));
    EXPECT_EQ((*p->array("x_m"))[1], -1.25f);
    EXPECT_EQ((*p->array("segment"))[0], -1.0f);
    EXPECT_TRUE(std::isnan((*p->array("c2c_dx_m"))[0]));
    EXPECT_EQ((*p->array("c2c_dx_m"))[2], -0.002f);
    EXPECT_FALSE(p->array("c2c_dz_m"));

    // Without a frame or points: "none", and nothing to read.
    const auto none = db.campaigns().get(bare);
    EXPECT_EQ(none->coarse, "none");
    EXPECT_FALSE(none->coarse_planes);
    EXPECT_FALSE(none->frame);
    EXPECT_FALSE(db.campaigns().points(bare));

    // Arrays of unequal lengths, or a frame that is not finite: refused, nothing stored.
    CampaignPoints uneven = points();
    uneven.arrays[2].values.pop_back();
    EXPECT_THROW(db.campaigns().add(campaign(3, 7000, reference), {}, uneven), StorageError);
    CampaignRow bad_frame = campaign(4, 7000, reference);
    bad_frame.frame = std::array<double, 16>{};
    (*bad_frame.frame)[3] = std::nan("");
    EXPECT_THROW(db.campaigns().add(bad_frame, {}, points()), StorageError);
    EXPECT_EQ(db.campaigns().in_range({}).size(), 2u);
}

TEST(CampaignStore, ACopyOrABadFigureIsRefusedWithNothingStored) {
    const test::TempDir dir("campaign-store-bad");
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto reference =
        db.epochs().insert({test::fake_sha256(900), 1000, "/ingest/r.ptx", 10, std::nullopt}).id;
    db.campaigns().add(campaign(1, 5000, reference), segments());
    EXPECT_THROW(db.campaigns().add(campaign(1, 6000, reference), segments()), StorageError);
    auto bad = segments();
    bad[0].parameters[3] = std::nan("");
    EXPECT_THROW(db.campaigns().add(campaign(2, 6000, reference), bad), StorageError);
    CampaignRow short_sha = campaign(3, 6000, reference);
    short_sha.sha256 = "abc";
    EXPECT_THROW(db.campaigns().add(short_sha, {}), StorageError);
    // A segment row that breaks the table (the same segment twice) leaves no campaign row.
    auto twice = segments();
    twice[1].segment = 0;
    EXPECT_THROW(db.campaigns().add(campaign(4, 6000, reference), twice), StorageError);
    EXPECT_FALSE(db.campaigns().find(test::fake_sha256(4)));
    EXPECT_EQ(db.campaigns().in_range({}).size(), 1u);
}

TEST(CampaignStore, ItsZoneRowsAreASeriesOfTheirOwnWithTheAlarmRowsOfItsTransaction) {
    const test::TempDir dir("campaign-store-zones");
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    const auto reference =
        db.epochs().insert({test::fake_sha256(900), 1000, "/ingest/r.ptx", 10, std::nullopt}).id;
    db.site().upsert_zone("pier_east", "{}");
    db.alarms().upsert_rule({0, "pier_east.bulge", "pier_east", kCampaignC2cMedian, "{}", true});
    // A station value of another quantity in the same zone: not mixed with the campaigns'.
    EpochResults station;
    station.outcome = EpochStatus::done;
    station.zone_results = {{"pier_east", "m3c2_median_m", 0.0007, 0.0004, 900, true}};
    ASSERT_TRUE(db.epochs().claim(reference));
    db.results().commit(reference, station);

    const auto evaluate = [](CampaignId id, const AlarmStore& alarms, const SeriesReader& series) {
        // Inside the transaction: the campaign's own row is in the series already.
        const auto points = series.points("pier_east", kCampaignC2cMedian, {});
        EXPECT_EQ(points.size(), 1u);
        EXPECT_EQ(alarms.rules().size(), 1u);
        AlarmRows rows;
        rows.states.push_back({"pier_east.bulge", "unack", "alarm", 5000, points.back().value,
                               std::nullopt, "alarm", std::nullopt, "", 5000});
        rows.events.push_back({5000, "pier_east.bulge", "raise", "alarm", points.back().value,
                               std::nullopt,
                               "normal -> unack (campaign " + std::to_string(id) + ")", "rule"});
        return rows;
    };
    const CampaignId first =
        db.campaigns().add(campaign(1, 5000, reference), segments(), {},
                           {{"pier_east", kCampaignC2cMedian, 0.021, 0.004, 340, true}}, evaluate);
    const CampaignId second =
        db.campaigns().add(campaign(2, 9000, reference), {}, {},
                           {{"pier_east", kCampaignC2cMedian, -0.001, 0.003, 310, false}});

    const auto series = db.series().points("pier_east", kCampaignC2cMedian, {});
    ASSERT_EQ(series.size(), 2u);
    EXPECT_EQ(series[0].campaign, first);
    EXPECT_EQ(series[0].epoch, 0);
    EXPECT_EQ(series[0].acquired, 5000);
    EXPECT_EQ(series[0].value, 0.021);
    EXPECT_EQ(series[0].uncertainty, 0.004);
    EXPECT_EQ(series[0].n, 340);
    EXPECT_TRUE(series[0].significant);
    EXPECT_EQ(series[0].datum, "campaign");
    EXPECT_EQ(series[1].campaign, second);
    EXPECT_EQ(db.series().points("pier_east", kCampaignC2cMedian, {{6000}, {}}).size(), 1u);
    // The station's series is untouched, and both quantities are the zone's.
    const auto m3c2 = db.series().points("pier_east", "m3c2_median_m", {});
    ASSERT_EQ(m3c2.size(), 1u);
    EXPECT_FALSE(m3c2[0].campaign);
    EXPECT_EQ(db.series().quantities("pier_east"),
              (std::vector<std::string>{kCampaignC2cMedian, "m3c2_median_m"}));
    const auto latest = db.series().latest_values();
    ASSERT_EQ(latest.size(), 2u);
    EXPECT_EQ(latest[0].quantity, kCampaignC2cMedian);
    EXPECT_EQ(latest[0].point.campaign, second);
    EXPECT_EQ(latest[0].point.value, -0.001);
    EXPECT_EQ(latest[1].quantity, "m3c2_median_m");
    EXPECT_EQ(db.campaigns().zone_results(first).size(), 1u);
    EXPECT_EQ(db.campaigns().zone_results(first)[0].value, 0.021);

    // The alarm rows were written with the first campaign.
    const auto states = db.alarms().states();
    ASSERT_EQ(states.size(), 1u);
    EXPECT_EQ(states[0].state, "unack");
    EXPECT_FALSE(states[0].epoch);
    const auto events = db.alarms().events(std::nullopt);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_NE(events[0].message.find("campaign " + std::to_string(first)), std::string::npos);

    // A station quantity, an unknown zone or a value that is not finite: nothing stored.
    EXPECT_THROW(db.campaigns().add(campaign(3, 9500, reference), {}, {},
                                    {{"pier_east", "m3c2_median_m", 0.001, 0.001, 10, false}}),
                 StorageError);
    EXPECT_THROW(db.campaigns().add(campaign(4, 9500, reference), {}, {},
                                    {{"nowhere", kCampaignC2cMedian, 0.001, 0.001, 10, false}}),
                 StorageError);
    EXPECT_THROW(
        db.campaigns().add(campaign(5, 9500, reference), {}, {},
                           {{"pier_east", kCampaignC2cMedian, std::nan(""), 0.001, 10, false}}),
        StorageError);
    EXPECT_EQ(db.campaigns().in_range({}).size(), 2u);
    EXPECT_EQ(db.series().points("pier_east", kCampaignC2cMedian, {}).size(), 2u);
}

}  // namespace
}  // namespace tlsmon
