// ResultsWriter::commit writes everything of an epoch in one transaction; the reads return it.
#include <SQLiteCpp/SQLiteCpp.h>
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
    Fixture() {
        db.site().upsert_zone("pier P3 top", R"({"box":[0,0,0,1,1,10]})");
        db.site().upsert_zone("segment 7", R"({"box":[10,0,0,20,1,2]})");
        db.alarms().upsert_rule({0, "P3 settlement", "pier P3 top", "m3c2_mean_m",
                                 R"({"high":0.005,"highhigh":0.01})", true});
    }
    EpochId claimed(int n, UtcSeconds t) {
        const auto id =
            db.epochs().insert({test::fake_sha256(n), t, "/ingest/s.ptx", 10, std::nullopt}).id;
        EXPECT_TRUE(db.epochs().claim(id));
        return id;
    }
    std::int64_t rows(const std::string& table) {
        SQLite::Database raw((dir / "e.sqlite").string(), SQLite::OPEN_READONLY);
        return raw.execAndGet("SELECT count(*) FROM " + table).getInt64();
    }
};

EpochResults full_results(EpochId id) {
    EpochResults r;
    r.point_count = 123456;
    r.timings = {1200.5, 300.25, 4000.0, 5600.75};
    r.archive_path = "/archive/2026/03/s.ptx";
    RegistrationRow reg;
    reg.method = "targets-helmert";
    for (int i = 0; i < 16; ++i) reg.transform[i] = (i % 5 == 0) ? 1.0 : 0.001 * i;
    reg.target_count = 4;
    reg.rms_m = 0.0012;
    reg.max_residual_m = 0.0021;
    reg.sigma0 = 0.98;
    reg.accepted = true;
    reg.quality_json = R"({"chi2_p":0.41})";
    r.registration = reg;
    r.targets.resize(2);
    r.targets[0].target = "T1";
    r.targets[0].kind = "sphere";
    r.targets[0].measured = {1, 2, 3};
    r.targets[0].residual = {0.001, -0.0005, 0.0002};
    r.targets[1].target = "T2";
    r.targets[1].kind = "plane";
    r.targets[1].measured = {4, 5, 6};
    r.targets[1].residual = {0.004, 0.0, -0.001};
    r.targets[1].stable = false;
    r.targets[1].used = false;
    r.zone_results = {{"pier P3 top", "m3c2_mean_m", -0.0042, 0.0018, 812, true},
                      {"pier P3 top", "keypoint_dz_m", -0.0038, std::nullopt, 41, false},
                      {"segment 7", "m3c2_mean_m", 0.0003, 0.0021, 2030, false}};
    std::vector<float> d(10000);
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = 0.001f * std::sin(0.01f * i);
    r.core_point_arrays = {{"m3c2_distance_m", d}, {"lod95_m", std::vector<float>(10000, 0.002f)}};
    r.alarm_states = {{"P3 settlement", "unack", "alert", 1000, -0.0042, id, "alert", std::nullopt,
                       "0:0 1:0 0:0", 1000}};
    r.alarm_events = {
        {1000, "P3 settlement", "raise", "alert", -0.0042, id, "P3 top settled 4.2 mm", "rule"}};
    r.system_events = {{1000, "info", "epoch_done", "epoch analysed", id}};
    return r;
}

TEST(EpochCommit, EverythingIsStoredAndReadBack) {
    Fixture f;
    const auto id = f.claimed(1, 1000);
    const auto results = full_results(id);
    f.db.results().commit(id, results);

    const auto e = f.db.epochs().find(id);
    EXPECT_EQ(e->status, EpochStatus::done);
    EXPECT_EQ(e->point_count, 123456);
    EXPECT_DOUBLE_EQ(e->timings.register_ms.value_or(-1), 300.25);
    EXPECT_DOUBLE_EQ(e->timings.total_ms.value_or(-1), 5600.75);
    EXPECT_EQ(e->archive_path.value_or(""), "/archive/2026/03/s.ptx");

    const auto reg = f.db.registrations().of_epoch(id);
    ASSERT_TRUE(reg);
    EXPECT_EQ(reg->transform, results.registration->transform);
    EXPECT_EQ(reg->target_count, 4);
    EXPECT_DOUBLE_EQ(reg->rms_m, 0.0012);
    EXPECT_EQ(reg->sigma0, 0.98);
    EXPECT_TRUE(reg->accepted);
    EXPECT_EQ(reg->quality_json, R"({"chi2_p":0.41})");

    const auto targets = f.db.registrations().targets_of_epoch(id);
    ASSERT_EQ(targets.size(), 2u);
    EXPECT_EQ(targets[1].target, "T2");
    EXPECT_EQ(targets[1].kind, "plane");
    EXPECT_DOUBLE_EQ(targets[1].residual[0], 0.004);
    EXPECT_FALSE(targets[1].stable);

    const auto series = f.db.series().points("pier P3 top", "m3c2_mean_m", {});
    ASSERT_EQ(series.size(), 1u);
    EXPECT_EQ(series[0].epoch, id);
    EXPECT_EQ(series[0].acquired, 1000);
    EXPECT_DOUBLE_EQ(series[0].value, -0.0042);
    EXPECT_EQ(series[0].uncertainty, 0.0018);
    EXPECT_EQ(series[0].n, 812);
    EXPECT_TRUE(series[0].significant);
    const auto kp = f.db.series().points("pier P3 top", "keypoint_dz_m", {});
    ASSERT_EQ(kp.size(), 1u);
    EXPECT_FALSE(kp[0].uncertainty);
    EXPECT_EQ(f.db.series().quantities("pier P3 top"),
              (std::vector<std::string>{"keypoint_dz_m", "m3c2_mean_m"}));

    const auto array = f.db.series().core_point_array(id, "m3c2_distance_m");
    ASSERT_TRUE(array);
    EXPECT_EQ(array->values, results.core_point_arrays[0].values);
    EXPECT_FALSE(f.db.series().core_point_array(id, "no_such_quantity"));

    const auto states = f.db.alarms().states();
    ASSERT_EQ(states.size(), 1u);
    EXPECT_EQ(states[0].state, "unack");
    EXPECT_EQ(states[0].epoch, id);
    const auto events = f.db.series().events({});
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].source, "system");  // same second: system before alarm
    EXPECT_EQ(events[1].source, "alarm");
    EXPECT_EQ(events[1].rule, "P3 settlement");
    EXPECT_EQ(events[1].message, "P3 top settled 4.2 mm");
}

// A failure in the middle of the transaction (here: the same zone and quantity twice, which
// violates the time series key) leaves nothing of the epoch and the epoch `processing`.
TEST(EpochCommit, FailureMidTransactionStoresNothing) {
    Fixture f;
    const auto id = f.claimed(1, 1000);
    auto results = full_results(id);
    results.zone_results.push_back(results.zone_results[0]);
    try {
        f.db.results().commit(id, results);
        FAIL() << "a duplicate zone result was accepted";
    } catch (const StorageError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("committing epoch " + std::to_string(id)), std::string::npos) << what;
        EXPECT_NE(what.find("UNIQUE"), std::string::npos) << what;
        EXPECT_FALSE(e.disk_full());
    }
    EXPECT_EQ(f.db.epochs().find(id)->status, EpochStatus::processing);
    EXPECT_FALSE(f.db.epochs().find(id)->point_count);
    for (const char* table :
         {"registrations", "target_observations", "quantities", "zone_results", "core_point_arrays",
          "alarm_states", "alarm_events", "system_events"}) {
        EXPECT_EQ(f.rows(table), 0) << table;
    }
    // The same epoch commits cleanly afterwards.
    f.db.results().commit(id, full_results(id));
    EXPECT_EQ(f.db.epochs().find(id)->status, EpochStatus::done);
    EXPECT_EQ(f.rows("zone_results"), 3);
}

TEST(EpochCommit, UnknownZoneIsRefusedWithItsName) {
    Fixture f;
    const auto id = f.claimed(1, 1000);
    EpochResults r;
    r.zone_results = {{"pier P3 top", "m3c2_mean_m", 0.001, 0.002, 10, false},
                      {"pier P9", "m3c2_mean_m", 0.001, 0.002, 10, false}};
    try {
        f.db.results().commit(id, r);
        FAIL();
    } catch (const StorageError& e) {
        EXPECT_NE(std::string(e.what()).find("no zone named 'pier P9'"), std::string::npos)
            << e.what();
    }
    EXPECT_EQ(f.rows("zone_results"), 0);
    EXPECT_EQ(f.db.epochs().find(id)->status, EpochStatus::processing);
}

TEST(EpochCommit, RejectedKeepsRegistrationButNoResults) {
    Fixture f;
    const auto id = f.claimed(1, 1000);
    EpochResults r = full_results(id);
    r.outcome = EpochStatus::rejected;
    EXPECT_THROW(f.db.results().commit(id, r), StorageError);  // no reason, has zone results
    r.reason = "registration RMS 12.0 mm > 5.0 mm";
    EXPECT_THROW(f.db.results().commit(id, r), StorageError);  // still has zone results
    r.zone_results.clear();
    r.core_point_arrays.clear();
    r.alarm_states.clear();
    r.alarm_events.clear();
    f.db.results().commit(id, r);
    EXPECT_EQ(f.db.epochs().find(id)->status, EpochStatus::rejected);
    EXPECT_EQ(f.db.epochs().find(id)->reason, "registration RMS 12.0 mm > 5.0 mm");
    EXPECT_TRUE(f.db.registrations().of_epoch(id));
    EXPECT_TRUE(f.db.series().points("pier P3 top", "m3c2_mean_m", {}).empty());
}

TEST(EpochCommit, CommitNeedsAClaimedEpoch) {
    Fixture f;
    const auto id =
        f.db.epochs().insert({test::fake_sha256(1), 1000, "/ingest/s.ptx", 10, std::nullopt}).id;
    EXPECT_THROW(f.db.results().commit(id, full_results(id)), StorageError);  // still pending
    EXPECT_EQ(f.rows("zone_results"), 0);
    EXPECT_EQ(f.db.epochs().find(id)->status, EpochStatus::pending);
}

TEST(EpochCommit, SeriesAndEpochRangesAndStatus) {
    Fixture f;
    // Four epochs at 15-minute spacing; the third is rejected, the fourth still pending.
    const UtcSeconds t0 = 1772366400;  // 2026-03-01T12:00:00Z
    for (int i = 0; i < 3; ++i) {
        const auto id = f.claimed(i + 1, t0 + 900 * i);
        EpochResults r;
        if (i == 2) {
            r.outcome = EpochStatus::rejected;
            r.reason = "2 of 4 targets unstable";
        } else {
            r.zone_results = {{"pier P3 top", "m3c2_mean_m", -0.001 * (i + 1), 0.002, 100, i > 0}};
        }
        f.db.results().commit(id, r);
    }
    f.db.epochs().insert({test::fake_sha256(9), t0 + 2700, "/ingest/late.ptx", 10, std::nullopt});
    f.db.epochs().set_reference(1);

    const auto all = f.db.series().points("pier P3 top", "m3c2_mean_m", {});
    ASSERT_EQ(all.size(), 2u);
    EXPECT_DOUBLE_EQ(all[1].value, -0.002);
    const auto late = f.db.series().points("pier P3 top", "m3c2_mean_m", {t0 + 1, std::nullopt});
    ASSERT_EQ(late.size(), 1u);
    EXPECT_EQ(late[0].acquired, t0 + 900);
    EXPECT_TRUE(f.db.series().points("segment 7", "m3c2_mean_m", {}).empty());
    EXPECT_TRUE(f.db.series().points("no such zone", "m3c2_mean_m", {}).empty());

    const auto middle = f.db.series().epochs_in_range({t0 + 900, t0 + 1800});
    ASSERT_EQ(middle.size(), 2u);
    EXPECT_EQ(middle[0].status, EpochStatus::done);
    EXPECT_EQ(middle[1].status, EpochStatus::rejected);
    EXPECT_EQ(f.db.series().epochs_in_range({}).size(), 4u);

    const auto s = f.db.series().status_summary();
    EXPECT_EQ(s.epochs_by_status.at(EpochStatus::done), 2);
    EXPECT_EQ(s.epochs_by_status.at(EpochStatus::rejected), 1);
    EXPECT_EQ(s.epochs_by_status.at(EpochStatus::pending), 1);
    EXPECT_EQ(s.epochs_by_status.at(EpochStatus::failed), 0);
    EXPECT_EQ(s.backlog, 1);
    EXPECT_EQ(s.oldest_pending, t0 + 2700);
    ASSERT_TRUE(s.last_done);
    EXPECT_EQ(s.last_done->acquired, t0 + 900);
    ASSERT_TRUE(s.last_failure);
    EXPECT_EQ(s.last_failure->reason, "2 of 4 targets unstable");
    EXPECT_EQ(s.reference_epoch, 1);
    EXPECT_GT(s.database_bytes, 4096);
    EXPECT_EQ(s.schema_version, EpochDatabase::latest_schema_version());
}

TEST(EpochCommit, EventsFilterByTimeAndKind) {
    Fixture f;
    f.db.events().record({100, "info", "start", "tlsmon 0.1.0 started", std::nullopt});
    f.db.events().record({200, "error", "disk_full", "database or disk is full", std::nullopt});
    f.db.alarms().record_event({150, "P3 settlement", "ack", "alert", std::nullopt, std::nullopt,
                                "acknowledged by SCADA", "SCADA"});
    EXPECT_THROW(f.db.events().record({300, "fatal", "x", "", std::nullopt}), StorageError);
    EXPECT_THROW(f.db.alarms().record_event(
                     {300, "no rule", "raise", "", std::nullopt, std::nullopt, "", "rule"}),
                 StorageError);
    const auto all = f.db.series().events({});
    ASSERT_EQ(all.size(), 3u);
    EXPECT_EQ(all[0].kind, "start");
    EXPECT_EQ(all[1].kind, "ack");
    EXPECT_EQ(all[2].kind, "disk_full");
    const auto window = f.db.series().events({120, 250});
    ASSERT_EQ(window.size(), 2u);
    EXPECT_EQ(window[0].time, 150);
    const auto full = f.db.series().events({}, std::string("disk_full"));
    ASSERT_EQ(full.size(), 1u);
    EXPECT_EQ(full[0].level, "error");
}

// The registrations of a window in three queries read back the same as epoch by epoch, and
// only the window's epochs.
TEST(EpochCommit, TheRegistrationsOfAWindowAreThoseOfItsEpochs) {
    Fixture f;
    std::vector<EpochId> ids;
    for (int n = 1; n <= 3; ++n) {
        ids.push_back(f.claimed(n, 1000 * n));
        auto r = full_results(ids.back());
        r.registration->rms_m = 0.001 * n;
        r.registration_zone_sigmas = {{"pier P3 top", 0.0005 * n}, {"segment 7", 0.0007 * n}};
        r.alarm_states.clear();
        r.alarm_events.clear();
        f.db.results().commit(ids.back(), r);
    }
    const auto window = f.db.registrations().in_range({2000, 3000});
    ASSERT_EQ(window.registration.size(), 2u);
    EXPECT_FALSE(window.registration.count(ids[0]));
    for (const EpochId id : {ids[1], ids[2]}) {
        const auto one = f.db.registrations().of_epoch(id);
        ASSERT_TRUE(one);
        EXPECT_EQ(window.registration.at(id).rms_m, one->rms_m);
        EXPECT_EQ(window.registration.at(id).transform, one->transform);
        const auto targets = f.db.registrations().targets_of_epoch(id);
        ASSERT_EQ(window.targets.at(id).size(), targets.size());
        for (std::size_t k = 0; k < targets.size(); ++k) {
            EXPECT_EQ(window.targets.at(id)[k].target, targets[k].target);
            EXPECT_EQ(window.targets.at(id)[k].residual, targets[k].residual);
        }
        const auto sigmas = f.db.registrations().zone_sigmas_of_epoch(id);
        ASSERT_EQ(window.zone_sigmas.at(id).size(), 2u);
        EXPECT_EQ(window.zone_sigmas.at(id)[1].max_sigma_3d_m, sigmas[1].max_sigma_3d_m);
    }
}

}  // namespace
}  // namespace tlsmon
