// Crash safety on the demo's scenario (issue 14; the kill -9 test of the epoch database,
// tests/daemon/test_process_daemon_crash.cpp, on the scenario with registration, M3C2 and
// alarms): 24 epochs with the knocked target and the step, the daemon killed with SIGKILL at
// random moments while they arrive three at a time and restarted each time, ends with the
// database of an uninterrupted run — every epoch once with the same outcome, the same
// registrations, the same zone values and per-core-point arrays byte for byte, the same alarm
// history and states. What may differ, and is left out: wall-clock times (discovered,
// updated, stage timings), file paths (another folder), and system events (the daemon's own
// log of starts and recoveries). No system alarm is expected in either run (as in the
// end-to-end test); any there is reported.
#include <gtest/gtest.h>

#include <iostream>
#include <map>
#include <random>

#include "tests/support/e2e_scenario.hpp"

namespace tlsmon::test::e2e {
namespace {

constexpr int kEpochs = 24;

// Rows keyed by the epoch's sha256, not its id (ids follow discovery order). Text with the
// run's folder replaced.
struct RunContents {
    std::map<std::string, std::string> epochs, registrations, targets, stages, zone_values,
        core_points;
    std::string reference, alarm_events, alarm_states, system_alarm_events;
};

std::string without(std::string text, const std::string& folder) {
    for (auto at = text.find(folder); at != std::string::npos; at = text.find(folder)) {
        text.replace(at, folder.size(), "<run>");
    }
    return text;
}

// Each row of `query` as text, keyed by its column `key` (several rows of a key joined).
std::map<std::string, std::string> keyed(const fs::path& db, const std::string& query,
                                         const std::string& key, const std::string& folder) {
    std::map<std::string, std::string> out;
    for (auto row : sql(db, query)) {
        const std::string k = row.at(key).dump();
        row.erase(key);
        out[k] += without(row.dump(), folder) + "\n";
    }
    return out;
}

std::string all_rows(const fs::path& db, const std::string& query, const std::string& folder) {
    std::string out;
    for (const auto& row : sql(db, query)) out += without(row.dump(), folder) + "\n";
    return out;
}

RunContents contents(const fs::path& db, const fs::path& folder) {
    const std::string f = folder.string();
    const std::string sha = "(SELECT sha256 FROM epochs e WHERE e.id = x.epoch_id)";
    RunContents c;
    c.epochs =
        keyed(db, "SELECT sha256, acquired, file_size, status, reason, point_count FROM epochs",
              "sha256", f);
    c.reference = all_rows(db,
                           "SELECT e.sha256 FROM reference_epoch r JOIN epochs e ON e.id = "
                           "r.epoch_id",
                           f);
    c.registrations = keyed(db,
                            "SELECT " + sha +
                                " AS sha, method, hex(transform) AS m, target_count, rms_m, "
                                "max_residual_m, sigma0, accepted, quality_json, status, reason, "
                                "sigma_omega_rad, sigma_tz_m, variance_factor, redundancy FROM "
                                "registrations x",
                            "sha", f);
    c.targets = keyed(db,
                      "SELECT " + sha +
                          " AS sha, target, status, use, measured_x, measured_y, measured_z, "
                          "residual_x, residual_y, residual_z, statistic FROM target_observations "
                          "x ORDER BY target",
                      "sha", f);
    c.stages = keyed(db,
                     "SELECT " + sha +
                         " AS sha, position, stage, rejected FROM epoch_stages x ORDER BY position",
                     "sha", f);
    c.zone_values = keyed(db,
                          "SELECT " + sha +
                              " AS sha, z.name AS zone, q.name AS quantity, value, uncertainty, "
                              "n, significant FROM zone_results x JOIN zones z ON z.id = "
                              "x.zone_id JOIN quantities q ON q.id = x.quantity_id ORDER BY "
                              "z.name, q.name",
                          "sha", f);
    c.core_points = keyed(db,
                          "SELECT " + sha +
                              " AS sha, quantity, count, hex(sha3(data)) AS digest FROM "
                              "core_point_arrays x ORDER BY quantity",
                          "sha", f);
    // Rule events carry the acquisition time of their epoch; SCADA/CLI and system events the
    // wall clock (none of the former here).
    c.alarm_events = all_rows(db,
                              "SELECT x.time, r.name, x.kind, x.level, x.value, " + sha +
                                  " AS sha, x.actor, x.message FROM alarm_events x JOIN "
                                  "alarm_rules r ON r.id = x.rule_id WHERE r.name NOT LIKE "
                                  "'system.%' ORDER BY x.time, x.id",
                              f);
    c.alarm_states = all_rows(db,
                              "SELECT r.name, x.state, x.level, x.since, x.value, " + sha +
                                  " AS sha, x.process, x.memory, x.evaluated FROM alarm_states "
                                  "x JOIN alarm_rules r ON r.id = x.rule_id WHERE r.name NOT "
                                  "LIKE 'system.%' ORDER BY r.name",
                              f);
    c.system_alarm_events = all_rows(db,
                                     "SELECT r.name, x.kind FROM alarm_events x JOIN alarm_rules "
                                     "r ON r.id = x.rule_id WHERE r.name LIKE 'system.%'",
                                     f);
    return c;
}

void expect_same(const std::map<std::string, std::string>& got,
                 const std::map<std::string, std::string>& want, const char* what) {
    EXPECT_EQ(got.size(), want.size()) << what;
    for (const auto& [k, v] : want) {
        const auto it = got.find(k);
        if (it == got.end()) {
            ADD_FAILURE() << what << ": missing for epoch " << k;
        } else {
            EXPECT_EQ(it->second, v) << what << " of epoch " << k;
        }
    }
}

TEST(EndToEndCrash, KilledAtRandomDuringTheDemoScenarioEqualsAnUninterruptedRun) {
    const auto t0 = std::chrono::steady_clock::now();
    const TempDir tmp("e2e-crash");
    const Scenario s = shared_scenario(kEpochs, next_midnight());
    ASSERT_EQ(s.stems.size(), static_cast<std::size_t>(kEpochs));

    // Uninterrupted: every file there, one `run --once`.
    const fs::path calm = tmp.path() / "calm";
    const fs::path calm_config = write_config(s, calm, 1502, false);
    for (int k = 0; k < kEpochs; ++k) feed(s, k, calm / "ingest");
    DaemonProcess once(calm_config, calm / "daemon.log", true);
    ASSERT_EQ(once.wait(300), 0) << read_text(calm / "daemon.log");
    const RunContents expected = contents(calm / "tlsmon.sqlite", calm);
    // Every epoch has its rows in each table compared (the comparison is not of empty sets).
    for (const auto* rows : {&expected.epochs, &expected.registrations, &expected.targets,
                             &expected.stages, &expected.zone_values, &expected.core_points}) {
        ASSERT_EQ(rows->size(), static_cast<std::size_t>(kEpochs));
    }

    // Killed: the epochs arrive three at a time; the daemon is restarted with each three and
    // killed -9 at a random moment: after it has committed 0, 1 or 2 more epochs, but never
    // the last one waiting, then a random pause of up to 600 ms (an epoch of this scene takes
    // about 0.5 s to read and analyse): inside the start, inside an epoch's analysis or its
    // commit. A kill that leaves an epoch `processing` in the database landed inside one.
    const fs::path killed = tmp.path() / "killed";
    const fs::path config = write_config(s, killed, 1502, false);
    const fs::path database = killed / "tlsmon.sqlite";
    std::mt19937 random(20261123);
    std::uniform_int_distribution<int> more(0, 2), pause_ms(0, 600);
    int kills = 0, inside_an_epoch = 0;
    for (int fed = 0; fed < kEpochs; ++kills) {
        for (int k = 0; k < 3 && fed < kEpochs; ++k) feed(s, fed++, killed / "ingest");
        const int target = std::min(fed - 1, processed(database) + more(random));
        DaemonProcess daemon(config, killed / "daemon.log");
        ASSERT_TRUE(wait_until([&] { return processed(database) >= target; }, 60))
            << read_text(killed / "daemon.log");
        std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(random)));
        daemon.signal(SIGKILL);
        ASSERT_EQ(daemon.wait(10), -2);
        if (fs::exists(database)) {
            inside_an_epoch +=
                sql(database, "SELECT count(*) AS n FROM epochs WHERE status = 'processing'")
                    .at(0)
                    .at("n")
                    .get<int>();
        }
    }
    const int before_last = processed(database);
    DaemonProcess last(config, killed / "daemon.log", true);
    ASSERT_EQ(last.wait(300), 0) << read_text(killed / "daemon.log");
    std::cout << kills << " kills, " << inside_an_epoch << " of them inside an epoch; "
              << before_last << " of " << kEpochs << " epochs processed before the last start; "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
              << " s in all\n";

    const RunContents got = contents(killed / "tlsmon.sqlite", killed);
    expect_same(got.epochs, expected.epochs, "epoch");
    EXPECT_EQ(got.reference, expected.reference);
    expect_same(got.registrations, expected.registrations, "registration");
    expect_same(got.targets, expected.targets, "target observations");
    expect_same(got.stages, expected.stages, "stages");
    expect_same(got.zone_values, expected.zone_values, "zone values");
    expect_same(got.core_points, expected.core_points, "core point arrays");
    EXPECT_EQ(got.alarm_events, expected.alarm_events);
    EXPECT_EQ(got.alarm_states, expected.alarm_states);
    // The step alarm is in that history once (exactly once, not once per restart).
    EXPECT_EQ(std::count(got.alarm_events.begin(), got.alarm_events.end(), '\n'), 1)
        << got.alarm_events;
    EXPECT_NE(got.alarm_events.find("\"south_top_step\""), std::string::npos);
    EXPECT_EQ(got.system_alarm_events, "") << "system alarms of the killed run";
    EXPECT_EQ(expected.system_alarm_events, "") << "system alarms of the uninterrupted run";
    EXPECT_EQ(sql(killed / "tlsmon.sqlite", "PRAGMA integrity_check").at(0).at("integrity_check"),
              "ok");
    EXPECT_EQ(sql(killed / "tlsmon.sqlite",
                  "SELECT count(*) AS n FROM epochs WHERE status IN ('pending', 'processing')")
                  .at(0)
                  .at("n"),
              0);
    // Every scan was moved out of the ingest folder, as in the uninterrupted run.
    const auto scans_in = [](const fs::path& folder) {
        std::vector<std::string> names;
        if (!fs::exists(folder)) return names;
        for (const auto& f : fs::recursive_directory_iterator(folder)) {
            if (f.path().extension() == ".ptx") names.push_back(f.path().filename().string());
        }
        std::sort(names.begin(), names.end());
        return names;
    };
    EXPECT_EQ(scans_in(killed / "ingest"), std::vector<std::string>{});
    EXPECT_EQ(scans_in(killed / "archive"), scans_in(calm / "archive"));
    EXPECT_EQ(scans_in(killed / "archive").size(), static_cast<std::size_t>(kEpochs));
}

}  // namespace
}  // namespace tlsmon::test::e2e
