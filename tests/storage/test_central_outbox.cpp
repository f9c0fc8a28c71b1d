// The central outbox (schema/0020_central_outbox.sql): written by triggers in the epoch's own
// transaction while forwarding is on, nothing while it is off; the history queued once when
// it is first switched on; reals exact to the double; entries gone once marked sent.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "storage/schema_migrations.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;
using nlohmann::json;

struct Fixture {
    test::TempDir dir;
    EpochDatabase db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    Fixture() {
        db.site().upsert_zone("pier", R"({"box":[0,0,0,1,1,10]})");
        db.alarms().upsert_rule(
            {0, "pier high", "pier", "m3c2_median_m", R"({"high":0.005})", true});
    }
    EpochId commit(int n, UtcSeconds t, double value) {
        const auto id =
            db.epochs().insert({test::fake_sha256(n), t, "/ingest/s.ptx", 10, std::nullopt}).id;
        EXPECT_TRUE(db.epochs().claim(id));
        EpochResults r;
        r.point_count = 1000;
        RegistrationRow reg;
        reg.method = "targets-helmert";
        reg.rms_m = 0.1 + 0.2;  // 0.30000000000000004: 17 digits tell it from 0.3
        reg.accepted = true;
        reg.parameters = std::array<double, 6>{1e-5, -2e-5, 3e-5, 0.001, -0.002, 1.0 / 3};
        r.registration = reg;
        r.zone_results = {{"pier", "m3c2_median_m", value, 0.0011, 812, true},
                          {"pier", "m3c2_mean_m", value / 3, std::nullopt, 812, false}};
        r.alarm_events = {{t, "pier high", "raise", "alarm", value, id, "high", "rule"}};
        r.system_events = {{t, "info", "epoch_done", "done", id}};
        db.results().commit(id, r);
        return id;
    }
    std::vector<OutboxEntry> all() { return db.central_outbox().pending(1000); }
};

TEST(CentralOutbox, NothingIsWrittenWhileForwardingIsOff) {
    Fixture f;
    f.commit(1, 1000, 0.004);
    EXPECT_TRUE(f.all().empty());
    const auto s = f.db.central_outbox().state();
    EXPECT_FALSE(s.enabled);
    EXPECT_EQ(s.pending, 0);
    EXPECT_EQ(s.database_id.size(), 32u);
}

TEST(CentralOutbox, SwitchedOnTheHistoryIsQueuedThenEachCommitAddsItsRows) {
    Fixture f;
    f.commit(1, 1000, 0.004);
    // Epoch, registration, two zone results, the alarm event, the system event.
    EXPECT_EQ(f.db.central_outbox().set_enabled(true), 6);
    EXPECT_EQ(f.db.central_outbox().set_enabled(true), 0);  // already on
    auto entries = f.all();
    ASSERT_EQ(entries.size(), 6u);
    EXPECT_EQ(entries[0].kind, "epoch");
    EXPECT_EQ(entries[1].kind, "registration");
    EXPECT_EQ(entries[2].kind, "zone_result");
    EXPECT_EQ(entries[3].kind, "zone_result");

    const double v = 0.1 + 0.7;  // 0.79999999999999993
    f.commit(2, 1900, v);
    entries = f.all();
    ASSERT_EQ(entries.size(), 12u);
    std::vector<std::string> kinds;
    for (std::size_t i = 6; i < entries.size(); ++i) {
        kinds.push_back(entries[i].kind);
        EXPECT_GT(entries[i].seq, entries[i - 1].seq);
    }
    EXPECT_EQ(kinds, (std::vector<std::string>{"epoch", "registration", "zone_result",
                                               "zone_result", "alarm_event", "system_event"}));
    const json epoch = json::parse(entries[6].payload);
    EXPECT_EQ(epoch.at("sha256"), test::fake_sha256(2));
    EXPECT_EQ(epoch.at("status"), "done");
    EXPECT_EQ(epoch.at("acquired"), 1900);
    const json reg = json::parse(entries[7].payload);
    EXPECT_EQ(reg.at("rms_m").get<double>(), 0.1 + 0.2);
    EXPECT_EQ(reg.at("parameters").at(5).get<double>(), 1.0 / 3);
    EXPECT_TRUE(reg.at("sigmas").is_null());
    const json zone = json::parse(entries[8].payload);
    EXPECT_EQ(zone.at("zone"), "pier");
    EXPECT_EQ(zone.at("value").get<double>(), v);  // exact: 17 significant digits
    const json mean = json::parse(entries[9].payload);
    EXPECT_TRUE(mean.at("uncertainty").is_null());
    const json alarm = json::parse(entries[10].payload);
    EXPECT_EQ(alarm.at("rule"), "pier high");
    EXPECT_EQ(alarm.at("zone"), "pier");
    EXPECT_EQ(alarm.at("sha256"), test::fake_sha256(2));

    // Switched off: nothing is written, the pending entries stay. Switched on again: the
    // whole history is queued, the epoch committed while off with it.
    EXPECT_EQ(f.db.central_outbox().set_enabled(false), 0);
    f.commit(3, 2800, 0.001);
    EXPECT_EQ(f.all().size(), 12u);
    EXPECT_EQ(f.db.central_outbox().set_enabled(true), 18);
    EXPECT_EQ(f.all().size(), 30u);
}

TEST(CentralOutbox, MarkedSentEntriesAreGoneAndAFailureIsKeptUntilASuccess) {
    Fixture f;
    f.db.central_outbox().set_enabled(true);
    f.commit(1, 1000, 0.004);
    f.commit(2, 1900, 0.005);
    const auto entries = f.all();
    ASSERT_EQ(entries.size(), 12u);
    f.db.central_outbox().record_failure("connection refused", 5000);
    f.db.central_outbox().record_failure("connection refused again", 5100);
    auto s = f.db.central_outbox().state();
    EXPECT_EQ(s.failing_since, 5000);
    EXPECT_EQ(s.last_error, "connection refused again");
    EXPECT_EQ(s.pending, 12);
    EXPECT_EQ(s.oldest_pending, entries[0].created);

    f.db.central_outbox().mark_sent(entries[5].seq, 5200);
    s = f.db.central_outbox().state();
    EXPECT_EQ(s.pending, 6);
    EXPECT_EQ(s.sent_upto, entries[5].seq);
    EXPECT_FALSE(s.failing_since);
    EXPECT_EQ(s.last_error, "");
    EXPECT_EQ(f.all().front().seq, entries[6].seq);
    // A batch confirmed again (sent twice after a crash) moves nothing back.
    f.db.central_outbox().mark_sent(entries[2].seq, 5300);
    EXPECT_EQ(f.db.central_outbox().state().sent_upto, entries[5].seq);
}

// The outbox is written in the epoch's transaction: a commit that fails leaves no entry.
TEST(CentralOutbox, AFailedCommitLeavesNoEntry) {
    Fixture f;
    f.db.central_outbox().set_enabled(true);
    const auto id =
        f.db.epochs().insert({test::fake_sha256(1), 1000, "/ingest/s.ptx", 10, std::nullopt}).id;
    ASSERT_TRUE(f.db.epochs().claim(id));
    EpochResults r;
    r.zone_results = {{"pier", "m3c2_median_m", 0.001, 0.001, 10, false},
                      {"pier", "m3c2_median_m", 0.001, 0.001, 10, false}};  // the key twice
    EXPECT_THROW(f.db.results().commit(id, r), StorageError);
    EXPECT_TRUE(f.all().empty());
}

// Migration 0022 makes the outbox anew for its wider CHECK: the entries not yet sent are kept
// and the sequence goes on past every seq given out before (none is used twice).
TEST(CentralOutbox, Migration22KeepsTheEntriesAndTheSequence) {
    test::TempDir dir;
    const auto path = dir / "epochs.sqlite";
    {
        SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
        raw.exec(
            "CREATE TABLE schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT NULL,"
            " applied INTEGER NOT NULL)");
        for (const auto& m : schema_migrations()) {
            if (m.version >= 22) break;
            raw.exec(m.sql);
            raw.exec("INSERT INTO schema_migrations VALUES (" + std::to_string(m.version) + ", '" +
                     m.name + "', 0)");
        }
        for (int k = 1; k <= 3; ++k)
            raw.exec("INSERT INTO outbox (created, kind, payload) VALUES (" + std::to_string(k) +
                     ", 'epoch', '{\"k\": " + std::to_string(k) + "}')");
        raw.exec("DELETE FROM outbox WHERE seq = 3");  // sent
        raw.exec("UPDATE central_forward SET sent_upto = 3");
    }
    auto db = EpochDatabase::open(path, EpochDatabase::Mode::read_write);
    EXPECT_EQ(db.schema_version(), EpochDatabase::latest_schema_version());
    const auto kept = db.central_outbox().pending(10);
    ASSERT_EQ(kept.size(), 2u);
    EXPECT_EQ(kept[1].seq, 2);
    EXPECT_EQ(kept[1].payload, "{\"k\": 2}");
    db.central_outbox().set_enabled(true);
    db.central_outbox().set_forward_arrays(true);
    const auto id = db.epochs().insert({test::fake_sha256(1), 1000, "/ingest/a.ptx", 10, {}}).id;
    db.epochs().claim(id);
    EpochResults r;
    r.core_point_arrays = {{"m3c2_distance_m", {1.5F, -2.25F}}};
    db.results().commit(id, r);
    const auto after = db.central_outbox().pending(10);
    ASSERT_GE(after.size(), 4u);  // the two kept, the array, the epoch (and its events)
    for (std::size_t i = 2; i < after.size(); ++i)  // after the 3 given out before the migration
        EXPECT_EQ(after[i].seq, static_cast<std::int64_t>(i) + 2) << after[i].kind;
    const auto array = std::find_if(after.begin(), after.end(),
                                    [](const auto& e) { return e.kind == "core_point_array"; });
    ASSERT_NE(array, after.end());
    // 1.5 and −2.25 as float32, little-endian.
    EXPECT_NE(array->payload.find("\"data\":\"0000c03f000010c0\""), std::string::npos)
        << array->payload;
}
}  // namespace
}  // namespace tlsmon
