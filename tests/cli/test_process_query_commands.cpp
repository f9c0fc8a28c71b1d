// `tlsmon status|query|events`: the built binary on a database filled through the storage
// API, checking the printed values in table, CSV and JSON.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "core/utc_time.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

// Standard output only, unless asked.
test::CommandRun run(const std::string& args, bool with_stderr = false) {
    return test::run_tlsmon(args, with_stderr);
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

std::string sha(int n) {
    std::string s(64, 'a');
    s.back() = static_cast<char>('0' + n);
    return s;
}

constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z

class QueryCommands : public ::testing::Test {
  protected:
    void SetUp() override {
        db_path_ = dir_ / "e.sqlite";
        auto db = EpochDatabase::open(db_path_, EpochDatabase::Mode::read_write);
        db.site().upsert_zone("pier P3 top", "{}");
        db.site().upsert_zone("segment 7", "{}");
        db.alarms().upsert_rule({0, "P3 settlement", "pier P3 top", "m3c2_mean_m", "{}", true});
        const double values[] = {-0.0012, -0.0042};
        for (int i = 0; i < 3; ++i) {
            const auto id =
                db.epochs()
                    .insert({sha(i), kT0 + 900 * i, "/ingest/s" + std::to_string(i) + ".ptx",
                             1000 + i, std::nullopt})
                    .id;
            db.epochs().claim(id);
            EpochResults r;
            if (i < 2) {
                r.point_count = 500000 + i;
                r.timings.total_ms = 2500.5;
                r.stages = {{"coverage", 12.25, "", "99.5 % inside"}, {"m3c2", 2000, "", ""}};
                r.zone_results = {{"pier P3 top", "m3c2_mean_m", values[i],
                                   i == 0 ? std::optional<double>() : std::optional<double>(0.0018),
                                   812 + i, i == 1},
                                  {"segment 7", "m3c2_mean_m", 0.0001, 0.002, 40, false}};
                if (i == 1) {  // registered on targets; epoch 1 has no registration row
                    r.registration = RegistrationRow{};
                    r.registration->method = "targets";
                    r.registration->status = "accepted";
                    r.registration->accepted = true;
                    // Two planes: the abutment's face left out as moved, the floor in the datum.
                    PlaneRow moved;
                    moved.plane = 3;
                    moved.role = "moved";
                    moved.normal = {0, -1, 0};
                    moved.centroid = {25.2, 56.0, 1.4};
                    moved.reference_points = 60952;
                    moved.epoch_points = 60100;
                    moved.change = {12.5 / 206264.806, -13.9 / 206264.806, 0.002636};
                    moved.sigma = {0.4 / 206264.806, 0.5 / 206264.806, 0.000029};
                    moved.statistic = 9644.3;
                    moved.critical = 7.81;
                    moved.significant = true;
                    PlaneRow floor = moved;
                    floor.plane = 0;
                    floor.role = "datum";
                    floor.zone = "";
                    floor.normal = {0, 0, 1};
                    floor.change = {0, 0, -0.000004};
                    floor.statistic = 0.3;
                    floor.significant = false;
                    r.planes = {floor, moved};
                }
            } else {
                r.outcome = EpochStatus::rejected;
                r.reason = "registration RMS 12.0 mm > 5.0 mm";
            }
            db.results().commit(id, r);
        }
        db.epochs().insert({sha(7), kT0 + 2700, "/ingest/s3.ptx", 1003, std::nullopt});
        db.epochs().set_reference(1);
        db.events().record({kT0 - 60, "info", "start", "tlsmon started", std::nullopt});
        db.events().record(
            {kT0 + 1000, "error", "disk_full", "write failed, \"/var\" full", std::nullopt});
        db.alarms().set_state({"P3 settlement", "unack", "H", kT0 + 900, -0.0042, 2, "H",
                               std::nullopt, "", kT0 + 900});
        db.alarms().record_event({kT0 + 900, "P3 settlement", "raise", "H", -0.0042, 2,
                                  "P3 top settled 4.2 mm", "rule"});
    }
    std::string db() const { return "--db " + db_path_.string(); }

    test::TempDir dir_;
    std::filesystem::path db_path_;
};

TEST_F(QueryCommands, SeriesAsCsv) {
    const auto r =
        run("query series --zone 'pier P3 top' --quantity m3c2_mean_m --format csv " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(lines(r.out), (std::vector<std::string>{
                                "epoch,acquired,value,uncertainty,n,significant,quality,datum",
                                "1,2026-03-01T12:00:00Z,-0.0012,,812,false,unregistered,"
                                "unregistered",
                                "2,2026-03-01T12:15:00Z,-0.0042,0.0018,813,true,accepted,targets",
                            }));
}

TEST_F(QueryCommands, SeriesAsJsonWithTimeRange) {
    const auto r =
        run("query series --zone 'pier P3 top' --quantity m3c2_mean_m --format json"
            " --from 2026-03-01T12:10Z --to 2026-03-01T13:00:00Z " +
            db());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0]["epoch"], 2);
    EXPECT_EQ(j[0]["acquired"], "2026-03-01T12:15:00Z");
    EXPECT_DOUBLE_EQ(j[0]["value"].get<double>(), -0.0042);
    EXPECT_DOUBLE_EQ(j[0]["uncertainty"].get<double>(), 0.0018);
    EXPECT_EQ(j[0]["significant"], true);
    // A time with an offset is converted to UTC: 13:10+01:00 is 12:10Z.
    const auto same =
        run("query series --zone 'pier P3 top' --quantity m3c2_mean_m"
            " --format json --from 2026-03-01T13:10+01:00 " +
            db());
    EXPECT_EQ(nlohmann::json::parse(same.out), j);
}

TEST_F(QueryCommands, SeriesAsTable) {
    const auto r = run("query series --zone 'segment 7' --quantity m3c2_mean_m " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto l = lines(r.out);
    ASSERT_EQ(l.size(), 3u);
    EXPECT_EQ(l[0].rfind("epoch  acquired", 0), 0u) << l[0];
    // Value and uncertainty in the quantity's unit (m3c2_mean_m: metres), so to the micrometre.
    EXPECT_NE(l[2].find("2026-03-01T12:15:00Z  0.000100  0.002000"), std::string::npos) << l[2];
    // Aligned columns, the last one (datum) included; quality and datum per epoch.
    EXPECT_EQ(l[1].rfind("unregistered  unregistered"), l[0].rfind("quality"));
    EXPECT_EQ(l[2].rfind("accepted"), l[0].rfind("quality")) << l[2];
    EXPECT_EQ(l[2].rfind("targets"), l[0].rfind("datum")) << l[2];
}

TEST_F(QueryCommands, PlanesOfAnEpoch) {
    // Epoch 2 (registered): its planes, the moved one in arc seconds and millimetres.
    auto r = run("query planes --epoch 2 " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto l = lines(r.out);
    ASSERT_EQ(l.size(), 3u) << r.out;
    EXPECT_TRUE(std::regex_search(l[0], std::regex("^plane +zone +role .*tilt_u_arcsec")));
    EXPECT_TRUE(std::regex_search(l[2], std::regex("^3 .* moved .* 12\\.50 .* 2\\.636 "))) << l[2];
    r = run("query planes --epoch 2 --format json " + db());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.size(), 2u);
    EXPECT_EQ(j[0]["role"], "datum");
    EXPECT_TRUE(j[0]["zone"].is_null());
    EXPECT_NEAR(j[1]["shift_mm"].get<double>(), 2.636, 1e-9);
    EXPECT_NEAR(j[1]["tilt_v_arcsec"].get<double>(), -13.9, 1e-6);
    EXPECT_EQ(j[1]["significant"], true);
    // Epoch 1 has none: an empty table and a note on stderr; an unknown epoch is an error.
    r = run("query planes --epoch 1 " + db(), true);
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("has no plane observations"), std::string::npos) << r.out;
    r = run("query planes --epoch 99 " + db(), true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("no epoch 99"), std::string::npos) << r.out;
}

TEST_F(QueryCommands, EpochsInAllFormats) {
    const auto json = run("query epochs --format json " + db());
    ASSERT_EQ(json.status, 0) << json.out;
    const auto j = nlohmann::json::parse(json.out);
    ASSERT_EQ(j.size(), 4u);
    EXPECT_EQ(j[0]["status"], "done");
    EXPECT_EQ(j[0]["points"], 500000);
    EXPECT_DOUBLE_EQ(j[0]["total_ms"].get<double>(), 2500.5);
    EXPECT_EQ(j[0]["stages"], "coverage 12.2 ms (99.5 % inside); m3c2 2000.0 ms");
    EXPECT_EQ(j[2]["status"], "rejected");
    EXPECT_EQ(j[2]["reason"], "registration RMS 12.0 mm > 5.0 mm");
    EXPECT_EQ(j[3]["status"], "pending");
    EXPECT_TRUE(j[3]["points"].is_null());
    EXPECT_EQ(j[3]["acquired"], "2026-03-01T12:45:00Z");

    const auto csv = run("query epochs --format csv --from 2026-03-01T12:30Z " + db());
    ASSERT_EQ(csv.status, 0);
    const auto l = lines(csv.out);
    ASSERT_EQ(l.size(), 3u);
    EXPECT_EQ(l[0], "epoch,acquired,status,points,total_ms,stages,file,size,sha256,reason");
    EXPECT_EQ(l[1], "3,2026-03-01T12:30:00Z,rejected,,,,/ingest/s2.ptx,1002," + sha(2) +
                        ",registration RMS 12.0 mm > 5.0 mm");

    // Relative to now: from 20 min after the first epoch on (the command runs within the
    // minute), up to a day ago and "now".
    const UtcSeconds minutes = (now_utc() - (kT0 + 20 * 60)) / 60;
    const auto relative = run("query epochs --format csv --from -" + std::to_string(minutes) +
                              "min --to now " + db());
    ASSERT_EQ(relative.status, 0) << relative.out;
    EXPECT_EQ(lines(relative.out).size(), 3u) << relative.out;
    EXPECT_EQ(lines(run("query epochs --format csv --to -1d " + db()).out).size(), 5u);

    const auto table = run("query epochs --to 2026-03-01T12:00:00Z " + db());
    ASSERT_EQ(table.status, 0);
    const auto t = lines(table.out);
    ASSERT_EQ(t.size(), 2u);
    EXPECT_NE(t[1].find("done"), std::string::npos);
    EXPECT_NE(t[1].find("/ingest/s0.ptx"), std::string::npos);
}

TEST_F(QueryCommands, EventsInAllFormats) {
    const auto csv = run("events --format csv " + db());
    ASSERT_EQ(csv.status, 0) << csv.out;
    EXPECT_EQ(
        lines(csv.out),
        (std::vector<std::string>{
            "time,time_base,source,level,kind,rule,epoch,message",
            "2026-03-01T11:59:00Z,system,system,info,start,,,tlsmon started",
            "2026-03-01T12:15:00Z,acquisition,alarm,H,raise,P3 settlement,2,P3 top settled 4.2 mm",
            "2026-03-01T12:16:40Z,system,system,error,disk_full,,,\"write failed, \"\"/var\"\" "
            "full\"",
        }));
    const auto json = run("events --format json --kind disk_full " + db());
    const auto j = nlohmann::json::parse(json.out);
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0]["message"], "write failed, \"/var\" full");
    EXPECT_TRUE(j[0]["epoch"].is_null());
    const auto table = run("events --from 2026-03-01T12:00Z --to 2026-03-01T12:15Z " + db());
    const auto t = lines(table.out);
    ASSERT_EQ(t.size(), 2u);
    EXPECT_NE(t[1].find("P3 top settled 4.2 mm"), std::string::npos);
}

TEST_F(QueryCommands, StatusInAllFormats) {
    const auto json = run("status --format json " + db());
    ASSERT_EQ(json.status, 0) << json.out;
    const auto j = nlohmann::json::parse(json.out);
    EXPECT_EQ(j["epochs_done"], 2);
    EXPECT_EQ(j["epochs_rejected"], 1);
    EXPECT_EQ(j["epochs_pending"], 1);
    EXPECT_EQ(j["backlog"], 1);
    EXPECT_EQ(j["oldest_pending"], "2026-03-01T12:45:00Z");
    EXPECT_EQ(j["last_epoch"], 2);
    EXPECT_EQ(j["last_epoch_acquired"], "2026-03-01T12:15:00Z");
    EXPECT_EQ(j["last_failure_reason"], "registration RMS 12.0 mm > 5.0 mm");
    EXPECT_EQ(j["reference_epoch"], 1);
    EXPECT_EQ(j["alarms_active"], 1);
    EXPECT_EQ(j["alarms_unacknowledged"], 1);
    ASSERT_EQ(j["alarm_states"].size(), 1u) << j.dump();
    EXPECT_EQ(j["alarm_states"][0]["rule"], "P3 settlement");
    EXPECT_EQ(j["alarm_states"][0]["state"], "unack");
    EXPECT_EQ(j["alarm_states"][0]["level"], "H");
    EXPECT_EQ(j["alarm_states"][0]["since"], "2026-03-01T12:15:00Z");
    EXPECT_EQ(
        j["database_bytes"].get<std::int64_t>(),
        static_cast<std::int64_t>(std::filesystem::file_size(db_path_) +
                                  (std::filesystem::exists(db_path_.string() + "-wal")
                                       ? std::filesystem::file_size(db_path_.string() + "-wal")
                                       : 0)));

    const auto csv = lines(run("status --format csv " + db()).out);
    ASSERT_FALSE(csv.empty());
    EXPECT_EQ(csv[0], "key,value");
    EXPECT_NE(std::find(csv.begin(), csv.end(), "backlog,1"), csv.end());
    const auto table = run("status " + db()).out;
    EXPECT_NE(table.find("last_failure_reason"), std::string::npos);
    EXPECT_NE(table.find("registration RMS 12.0 mm > 5.0 mm"), std::string::npos);
}

TEST_F(QueryCommands, DatabaseFromConfig) {
    test::write_file(dir_ / "site.toml", "[paths]\ndatabase = \"e.sqlite\"\n");
    const auto r = run("status --format json --config " + (dir_ / "site.toml").string());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out)["database"], db_path_.string());
}

TEST_F(QueryCommands, MistakesAreClearErrors) {
    auto r = run("query series --zone 'pier P9' --quantity m3c2_mean_m " + db(), true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("no zone 'pier P9'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("pier P3 top, segment 7"), std::string::npos) << r.out;
    r = run("query series --zone 'pier P3 top' --quantity m3c2_mean " + db(), true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("no quantity 'm3c2_mean'"), std::string::npos) << r.out;
    r = run("query epochs --from 01.03.2026 " + db(), true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("--from: time '01.03.2026'"), std::string::npos) << r.out;
    r = run("query epochs --from 2026-03-02 --to 2026-03-01 " + db(), true);
    EXPECT_EQ(r.status, 1);
    r = run("query epochs --to -7y " + db(), true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("--to: time '-7y'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("unknown unit 'y'"), std::string::npos) << r.out;
    r = run("status --db " + (dir_ / "missing.sqlite").string(), true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("missing.sqlite: no such epoch database"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "missing.sqlite"));
    r = run("status", true);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("--db PATH or --config FILE"), std::string::npos) << r.out;
    r = run("status --format xml " + db(), true);
    EXPECT_NE(r.status, 0);
}

}  // namespace
}  // namespace tlsmon
