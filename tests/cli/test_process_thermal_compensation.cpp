// Thermal compensation end to end: three days of the `small` scene with weather rendered by
// `tlsmon simulate` (the demo's five spheres at 0.07°, the pier seen to 30° elevation), one
// epoch's meteo sidecar taken away; `tlsmon run --once` with [thermal] (training_days = 2)
// and an alarm rule on the compensated south face. Checked against the simulator's truth and
// the database (sqlite3, not tlsmon's storage code): the model fitted once the series is two
// days long, each compensated value is measured − predicted, the residual of the last day far
// below the raw series' thermal swing, the epoch without meteo flagged `no_meteo` with an
// event and no compensated value; `tlsmon query thermal-models` and bad [thermal] keys. Then
// the daemon serves that database: the series API validates against docs/openapi.yaml with
// its `thermal` part, and Debian's chromium (headless) draws the zone page with the measured,
// predicted and compensated series holding exactly the database's values and bounds, the runs
// of epochs not compensated marked, and the measured series alone on request.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "report/truth.hpp"
#include "tests/support/dashboard_browser.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/modbus_client.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/small_scene.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace fs = std::filesystem;
using tlsmon::test::run_tlsmon;
using tlsmon::test::e2e::sql;

namespace {

constexpr int kEpochs = 3 * 96;
constexpr int kNoMeteoEpoch = 260;  // on the third day, after the model is fitted

const std::string kThermal =
    "\n[thermal]\nenabled = true\nlatitude_deg = 49.97\nlongitude_deg = 7.07\n"
    "training_days = 2\n";
const std::string kRule =
    "\n[[alarm.rule]]\nname = \"south_structural\"\nzone = \"pier_south_face\"\n"
    "quantity = \"m3c2_median_compensated_m\"\nalarm = { high = 0.003, low = -0.003 }\n";
const std::string kDaemon =
    "\n[registration]\nmax_sigma_angle_arcsec = 20\n"  // the 0.1° spheres: σ(ω) 8–18″
    "\n[paths]\ningest = \"scans\"\ndatabase = \"tlsmon.sqlite\"\narchive = \"archive\"\n"
    "quarantine = \"quarantine\"\n\n[ingest]\narchive = \"keep\"\nstable_seconds = 0\n"
    // The lost sidecar is not waited for two minutes, and only M3C2 is modelled: the keypoints
    // and the primitives would take five sixths of the run (65 s against 11 s, 288 epochs).
    "\n[meteo]\nwait_seconds = 5\n\n[keypoints]\nenabled = false\n\n[primitives]\nenabled = "
    "false\n";

// The site the simulator describes, PB-M3C2 off (the compensation models M3C2's medians), and
// the south face's zone drawn the cylinders' radius (0.5 m) inside the face's vertical edges,
// as docs/m3c2.md advises: the whole face's zone puts cylinders across the corners, whose
// distances depend on how M3C2 treats another face entering a cylinder (docs/m3c2.md, "Stray
// points at a face's edge"), and a change of a few hundredths of a millimetre in the zone's
// median can move the lag grid's choice (docs/thermal.md). This test is of the compensation.
std::string site_text(const fs::path& scans) {
    std::string site = tlsmon::test::read_text(scans / "site.toml");
    const auto replace = [&site](const std::string& from, const std::string& to) {
        const auto at = site.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) site.replace(at, from.size(), to);
    };
    replace("[pbm3c2]\nenabled = true", "[pbm3c2]\nenabled = false");
    replace("name = \"pier_south_face\"\nmin = [2, 44.5, 0]\nmax = [17, 45.5, 40]",
            "name = \"pier_south_face\"\nmin = [2.5, 44.5, 0]\nmax = [16.5, 45.5, 40]");
    return site;
}

// The zone page of `zone` as the browser drew it, against the database: each series' points
// (mm) and bounds those stored, epoch by epoch; the runs of epochs not compensated those of
// thermal_compensations.
void dashboard_draws_the_thermal_parts(const fs::path& config, const fs::path& db,
                                       const std::string& zone) {
    using tlsmon::test::e2e::quoted;
    const int port = tlsmon::test::free_tcp_port();
    tlsmon::test::write_text(config, tlsmon::test::read_text(config) +
                                         "\n[http]\nenabled = true\naddress = \"127.0.0.1\"\n"
                                         "port = " +
                                         std::to_string(port) + "\n");
    const fs::path log = db.parent_path() / "daemon.log";
    tlsmon::test::DaemonProcess daemon(config, log);
    const std::string base = "http://127.0.0.1:" + std::to_string(port);
    ASSERT_TRUE(tlsmon::test::wait_until(
        [&] { return tlsmon::test::shell("curl -s -f " + base + "/api/v1/site").status == 0; }, 60))
        << tlsmon::test::read_text(log);
    const auto openapi =
        tlsmon::test::shell("/usr/bin/python3 " +
                            quoted(std::string(TLSMON_SOURCE_DIR) + "/tests/web/openapi_check.py") +
                            " " + quoted(std::string(TLSMON_SOURCE_DIR) + "/docs/openapi.yaml") +
                            " " + base + " --series " + zone + " m3c2_median_m");
    EXPECT_EQ(openapi.status, 0) << openapi.output;

    const fs::path artifacts = tlsmon::test::browser_artifacts("thermal-dashboard");
    const auto seen = tlsmon::test::dashboard_browser(
        "thermal " + base + " " + quoted(artifacts.string()) + " " + zone + " m3c2_median_m",
        artifacts);
    for (const auto& [page, errors] : seen.at("errors").items())
        EXPECT_TRUE(errors.empty()) << page << ": " << errors.dump();
    // What the database holds, in mm by acquisition time.
    std::map<std::string, std::map<std::int64_t, std::pair<double, double>>> stored;
    for (const auto& r : sql(db,
                             "SELECT e.acquired AS t, q.name AS quantity, r.value AS value, "
                             "ifnull(r.uncertainty, 0) AS bound FROM zone_results r JOIN epochs e "
                             "ON e.id = r.epoch_id JOIN zones z ON z.id = r.zone_id JOIN "
                             "quantities q ON q.id = r.quantity_id WHERE z.name = '" +
                                 zone + "'"))
        stored[r.at("quantity")][r.at("t")] = {r.at("value").get<double>() * 1e3,
                                               r.at("bound").get<double>() * 1e3};
    const auto same = [&](const nlohmann::json& column, const std::string& quantity) {
        const auto& want = stored.at(quantity);
        EXPECT_EQ(column.size(), want.size()) << quantity;
        for (const auto& p : column) {
            const auto it = want.find(std::llround(p.at(0).get<double>()));
            ASSERT_NE(it, want.end()) << quantity << " at " << p.dump();
            EXPECT_NEAR(p.at(1).get<double>(), it->second.first, 1e-9) << quantity;
            EXPECT_NEAR(p.at(2).get<double>(), it->second.second, 1e-9) << quantity;
        }
    };
    const auto& measured = seen.at("measured");
    EXPECT_EQ(measured.at("labels"),
              nlohmann::json::array({"time", "m3c2_median_m [mm]", "thermal prediction [mm]",
                                     "compensated (measured − predicted) [mm]"}));
    same(measured.at("columns").at("m3c2_median_m [mm]"), "m3c2_median_m");
    same(measured.at("columns").at("thermal prediction [mm]"), "m3c2_median_thermal_m");
    same(measured.at("columns").at("compensated (measured − predicted) [mm]"),
         "m3c2_median_compensated_m");
    EXPECT_TRUE(measured.at("toggle_shown"));
    EXPECT_NE(measured.at("note").get<std::string>().find("thermal model v1"), std::string::npos)
        << measured.at("note");
    // The runs of epochs not compensated: the two days before the model, the lost sidecar (and
    // any extrapolated ones beyond the two training days' weather).
    int runs = 0;
    std::map<std::string, int> runs_of;
    std::string last = "compensated";
    for (const auto& c : sql(db,
                             "SELECT c.quality FROM thermal_compensations c JOIN epochs e ON "
                             "e.id = c.epoch_id WHERE c.zone = '" +
                                 zone + "' ORDER BY e.acquired")) {
        const std::string q = c.at("quality");
        if (q != "compensated" && q != last) ++runs, ++runs_of[q];
        last = q;
    }
    EXPECT_EQ(runs_of["no_model"], 1);
    EXPECT_EQ(runs_of["no_meteo"], 1);
    EXPECT_EQ(measured.at("drawn").at("runs"), runs);
    const auto& compensated = seen.at("compensated");
    EXPECT_EQ(compensated.at("labels"),
              nlohmann::json::array({"time", "m3c2_median_compensated_m [mm]", "measured [mm]",
                                     "thermal prediction [mm]"}));
    same(compensated.at("columns").at("measured [mm]"), "m3c2_median_m");
    // "measured only": the page's own quantity alone, nothing marked.
    const auto& alone = seen.at("measured_only");
    EXPECT_EQ(alone.at("labels"),
              nlohmann::json::array({"time", "m3c2_median_compensated_m [mm]"}));
    EXPECT_EQ(alone.at("drawn").at("runs"), 0);
}

}  // namespace

TEST(ThermalCompensation, LearnsTheDailySwingAndLeavesTheStructure) {
    const tlsmon::test::TempDir dir("thermal");
    tlsmon::test::write_text(dir / "scene.toml", tlsmon::test::small_scene_text(31));
    const auto sim = run_tlsmon("simulate --config " + (dir / "scene.toml").string() + " --out " +
                                (dir / "scans").string() + " --epochs " + std::to_string(kEpochs));
    ASSERT_EQ(sim.status, 0) << sim.out;
    const auto truths = tlsmon::report::read_truth_folder(dir / "scans");
    ASSERT_EQ(truths.size(), static_cast<std::size_t>(kEpochs));
    // One epoch's weather station file is lost.
    const std::string lost_stem =
        "small_" + tlsmon::format_utc(truths[kNoMeteoEpoch].time_unix).substr(0, 19);
    std::size_t removed = 0;
    for (const auto& f : fs::directory_iterator(dir / "scans")) {
        const std::string name = f.path().filename().string();
        std::string compact = lost_stem;
        std::erase(compact, '-');
        std::erase(compact, ':');
        if (name.ends_with(".meteo.csv") && name.starts_with(compact)) removed += fs::remove(f);
    }
    ASSERT_EQ(removed, 1u) << lost_stem;

    const fs::path config = dir / "site.toml";
    tlsmon::test::write_text(config, site_text(dir / "scans") + kThermal + kRule + kDaemon);
    const auto run = run_tlsmon("run --once --config " + config.string());
    ASSERT_EQ(run.status, 0) << run.out;
    const fs::path db = dir / "tlsmon.sqlite";

    // One model per zone, fitted by the first epoch two days after the first.
    const auto models = sql(db,
                            "SELECT m.zone, m.version, m.observations, m.surface_lag_h, "
                            "m.section_lag_h, m.prediction_sigma, e.acquired - m.training_from "
                            "AS span FROM thermal_models m JOIN epochs e ON e.id = m.epoch_id "
                            "ORDER BY m.zone");
    ASSERT_EQ(models.size(), 2u) << models.dump();
    const std::int64_t first = truths.front().time_unix;
    for (const auto& m : models) {
        EXPECT_EQ(m.at("version"), 1);
        EXPECT_GT(m.at("observations").get<int>(), 48);
        EXPECT_LT(m.at("prediction_sigma").get<double>(), 0.5e-3);
    }
    const auto fitted =
        sql(db,
            "SELECT min(e.acquired) AS t FROM thermal_compensations c JOIN epochs e "
            "ON e.id = c.epoch_id WHERE c.model_version IS NOT NULL");
    EXPECT_EQ(fitted.at(0).at("t").get<std::int64_t>(), first + 2 * 86400);

    // Every compensated value is measured − predicted; its bound the σ's 95 %.
    const auto rows = sql(
        db,
        "SELECT e.acquired, z.name AS zone, q.name AS quantity, r.value, r.uncertainty FROM "
        "zone_results r JOIN epochs e ON e.id = r.epoch_id JOIN zones z ON z.id = r.zone_id JOIN "
        "quantities q ON q.id = r.quantity_id WHERE q.name IN ('m3c2_median_m', "
        "'m3c2_median_thermal_m', 'm3c2_median_compensated_m')");
    std::map<std::string, std::map<std::int64_t, std::map<std::string, double>>> v;
    for (const auto& r : rows)
        v[r.at("zone")][r.at("acquired")][r.at("quantity")] = r.at("value").get<double>();
    for (const auto& [zone, epochs] : v) {
        int compensated = 0;
        for (const auto& [t, q] : epochs) {
            if (!q.contains("m3c2_median_compensated_m")) continue;
            ++compensated;
            EXPECT_NEAR(q.at("m3c2_median_compensated_m"),
                        q.at("m3c2_median_m") - q.at("m3c2_median_thermal_m"), 1e-12);
        }
        // The third day's epochs but the one without meteo.
        const auto done = sql(db,
                              "SELECT count(*) AS n FROM epochs WHERE status = 'done' AND "
                              "acquired >= " +
                                  std::to_string(first + 2 * 86400));
        EXPECT_EQ(compensated, done.at(0).at("n").get<int>() - 1) << zone;
        EXPECT_GT(compensated, 80) << zone;
    }

    // The last day against the truth (no event: the structural part is zero): the residual's
    // RMS a small part of the raw series' swing that day.
    const auto face =
        tlsmon::report::zone_face(truths.front().pier, {{2, 44.5, 0}, {17, 45.5, 40}});
    ASSERT_TRUE(face);
    double raw_lo = 1e9, raw_hi = -1e9, sum2 = 0;
    int n = 0;
    for (const auto& [t, q] : v.at("pier_south_face")) {
        if (!q.contains("m3c2_median_compensated_m")) continue;
        raw_lo = std::min(raw_lo, q.at("m3c2_median_m"));
        raw_hi = std::max(raw_hi, q.at("m3c2_median_m"));
        sum2 += std::pow(q.at("m3c2_median_compensated_m"), 2);
        ++n;
    }
    const double swing = raw_hi - raw_lo, rms = std::sqrt(sum2 / n);
    EXPECT_GT(swing, 1.5e-3);
    EXPECT_LT(rms, swing / 4) << "swing " << swing << " residual RMS " << rms;

    // The epoch without meteo: flagged, said in an event, no thermal values.
    const auto lost = sql(db,
                          "SELECT c.zone, c.quality, c.reason FROM thermal_compensations c JOIN "
                          "epochs e ON e.id = c.epoch_id WHERE e.acquired = " +
                              std::to_string(truths[kNoMeteoEpoch].time_unix));
    ASSERT_EQ(lost.size(), 2u);
    for (const auto& l : lost) {
        EXPECT_EQ(l.at("quality"), "no_meteo");
        EXPECT_NE(l.at("reason").get<std::string>().find("no meteo"), std::string::npos);
    }
    const auto said = sql(db,
                          "SELECT count(*) AS n FROM system_events WHERE kind = "
                          "'thermal_compensation' AND message LIKE '%: no_meteo (was %'");
    EXPECT_EQ(said.at(0).at("n"), 2);  // one per zone; and one each when it is back
    const auto back = sql(db,
                          "SELECT count(*) AS n FROM system_events WHERE kind = "
                          "'thermal_compensation' AND message LIKE '%(was no_meteo)%'");
    EXPECT_EQ(back.at(0).at("n"), 2);

    // No structural change: the rule on the compensated series never raised.
    const auto raised = sql(db,
                            "SELECT count(*) AS n FROM alarm_events a JOIN alarm_rules r ON r.id = "
                            "a.rule_id WHERE r.name = 'south_structural' AND a.kind = 'raise'");
    EXPECT_EQ(raised.at(0).at("n"), 0);

    // What an analyst reads.
    const auto query =
        run_tlsmon("query thermal-models --format json --config " + config.string(), false);
    ASSERT_EQ(query.status, 0) << query.out;
    const auto listed = nlohmann::json::parse(query.out);
    ASSERT_EQ(listed.size(), 2u);
    EXPECT_EQ(listed[0].at("zone"), "pier_south_face");
    EXPECT_NE(listed[0].at("coefficients").get<std::string>().find("solar_south="),
              std::string::npos);
    const auto flags = run_tlsmon(
        "query thermal-models --compensations --zone pier_west_face "
        "--format csv --config " +
            config.string(),
        false);
    ASSERT_EQ(flags.status, 0) << flags.out;
    EXPECT_NE(flags.out.find(",no_meteo,"), std::string::npos);
    EXPECT_NE(flags.out.find(",compensated,"), std::string::npos);

    dashboard_draws_the_thermal_parts(config, db, "pier_south_face");
}

TEST(ThermalCompensation, BadKeysAreRefusedWithTheKey) {
    const tlsmon::test::TempDir dir("thermal-config");
    const auto check = [&](const std::string& text) {
        tlsmon::test::write_text(dir / "site.toml", text);
        return run_tlsmon("check-config " + (dir / "site.toml").string());
    };
    const std::string zone =
        "[[zone]]\nname = \"face\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nnormal = [0, -1, 0]\n";
    auto r = check(zone + "[thermal]\nenabled = true\n");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("thermal.latitude_deg"), std::string::npos) << r.out;
    r = check(zone +
              "[thermal]\nenabled = true\nlatitude_deg = 50\nlongitude_deg = 7\n"
              "quantities = [\"m3c2_spread\"]\n");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("thermal.quantities"), std::string::npos) << r.out;
    r = check(zone +
              "[thermal]\nenabled = true\nlatitude_deg = 50\nlongitude_deg = 7\n"
              "zones = [\"deck\"]\n");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("no [[zone]] is named 'deck'"), std::string::npos) << r.out;
    r = check(zone + "[thermal]\nenabled = true\nlatitude_deg = 91\nlongitude_deg = 7\n");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("thermal.latitude_deg"), std::string::npos) << r.out;
    // A rule may watch the compensated series only when it is stored.
    const std::string rule =
        "[[alarm.rule]]\nname = \"r\"\nzone = \"face\"\nquantity = "
        "\"m3c2_median_compensated_m\"\nalarm = { high = 0.002 }\n";
    r = check(zone + rule);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("m3c2_median_compensated_m"), std::string::npos) << r.out;
    r = check(zone + "[thermal]\nenabled = true\nlatitude_deg = 50\nlongitude_deg = 7\n" + rule);
    EXPECT_EQ(r.status, 0) << r.out;
}
