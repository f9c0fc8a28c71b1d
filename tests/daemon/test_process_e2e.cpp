// The whole chain, scanner file to SCADA register, on the demo's scenario against the
// simulator's truth (issue 14, "Proof"): 24 epochs of the `small` scene with the knocked
// target (epoch 6) and the step of the south face's top band (epoch 12), fed one epoch at a
// time to a running daemon with Modbus on. Asserted:
//   - registration: the error at the pier's points against the exact H₀⁻¹·Hᵢ within issue
//     10's bounds (≤ 1 mm RMS per epoch; within the predicted 2σ in ≥ 90 % of epochs); the
//     knocked target excluded from its epoch on, no other target ever;
//   - M3C2: zone median − true change along the normal ≤ 0.5 mm RMS on the faces the scanner
//     faces (issue 11);
//   - alarms: the step rule raised within on_delay + 1 epochs of the step, acknowledged by
//     writing its coil with `mbpoll` while the daemon runs (state and SCADA event in the
//     database); nothing else raised: no other rule, no system alarm;
//   - Modbus: every register of the map read with `mbpoll` equals the database (read with
//     the sqlite3 program) decoded by the register map of docs/modbus.md;
//   - `tlsmon query` / `tlsmon alarms history` output equals the database.
// The truth comes from the truth files (docs/simulator.md), the database from sqlite3: the
// test uses neither tlsmon's report nor its storage code for what it compares.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "formats/las_reader.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/independent_las.hpp"
#include "tests/support/modbus_client.hpp"
#include "tests/support/seconds_since.hpp"

namespace tlsmon::test::e2e {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kEpochs = 24;

// IEEE 754 binary32 from two words, high word first (ABCD, docs/modbus.md).
float float_of(std::uint32_t high, std::uint32_t low) {
    const std::uint32_t bits = (high << 16) | low;
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}
std::uint32_t bits_of(float f) {
    std::uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

// What the register map says a zone's block holds, from the database.
struct Block {
    std::string zone, quantity;
    int address = 0;
    std::optional<double> value, lod, rate;
    int quality = 0, level = 0, state = 0;
};

int level_code(const std::string& l) {  // docs/modbus.md, `.alarm_level`
    return l == "warning" ? 1 : l == "alert" ? 2 : l == "alarm" ? 3 : 0;
}
int state_code(const std::string& s) {  // docs/modbus.md, `.isa_state`
    const char* states[] = {"normal", "unack", "ack", "rtn_unack", "shelved", "out_of_service"};
    for (int i = 0; i < 6; ++i) {
        if (s == states[i]) return i;
    }
    return -1;
}

// The whole map as the database says it should read at wall time `now`, compared with what
// mbpoll reads; "" when every register and bit agrees, else the differences.
std::string compare_registers(int port, const fs::path& db,
                              const std::vector<std::string>& quantities, double stale_seconds) {
    std::ostringstream diff;
    const std::int64_t now = now_utc();
    const std::vector<std::uint32_t> fixed = mbpoll_read(port, "3:hex", 0, 9);
    if (fixed.empty()) return "mbpoll could not read the fixed registers";

    const json summary = sql(db,
                             "SELECT (SELECT count(*) FROM epochs WHERE status IN "
                             "('done','rejected','failed')) AS processed, (SELECT count(*) FROM "
                             "epochs WHERE status IN ('pending','processing')) AS waiting, "
                             "(SELECT acquired FROM epochs WHERE status = 'done' ORDER BY acquired "
                             "DESC, id DESC LIMIT 1) AS last_done")
                             .at(0);
    const std::int64_t last_done =
        summary.at("last_done").is_null() ? 0 : summary.at("last_done").get<std::int64_t>();
    const json rules = sql(db,
                           "SELECT r.id, r.name, r.quantity, z.name AS zone, "
                           "coalesce(s.state, 'normal') AS state, coalesce(s.level, '') AS level "
                           "FROM alarm_rules r JOIN zones z ON z.id = r.zone_id LEFT JOIN "
                           "alarm_states s ON s.rule_id = r.id ORDER BY r.id");
    bool any_alarm = false, any_unack = false;
    for (const auto& r : rules) {
        any_alarm |= level_code(r.at("level")) > 0;
        any_unack |= r.at("state") == "unack" || r.at("state") == "rtn_unack";
    }
    const auto expect_word = [&](int address, std::uint32_t want, const char* name) {
        if (fixed[static_cast<std::size_t>(address)] != want) {
            diff << name << " [" << address << "] reads "
                 << fixed[static_cast<std::size_t>(address)] << ", the database says " << want
                 << "\n";
        }
    };
    expect_word(0, 1, "map_version");
    // running, database readable, epochs waiting, (no failure), stale, any alarm
    const std::uint32_t status = 1u | 2u | (summary.at("waiting").get<int>() > 0 ? 4u : 0u) |
                                 (static_cast<double>(now - last_done) > stale_seconds ? 16u : 0u) |
                                 (any_alarm ? 32u : 0u);
    expect_word(2, status, "daemon_status");
    const auto u32 = [&](int a) {
        return (fixed[static_cast<std::size_t>(a)] << 16) | fixed[static_cast<std::size_t>(a) + 1];
    };
    if (u32(3) != static_cast<std::uint32_t>(last_done)) {
        diff << "last_epoch_time reads " << u32(3) << ", the database says " << last_done << "\n";
    }
    if (u32(5) != summary.at("processed").get<std::uint32_t>()) {
        diff << "epochs_processed reads " << u32(5) << ", the database says "
             << summary.at("processed") << "\n";
    }
    if (float_of(fixed[7], fixed[8]) != 123456.0f) diff << "test_float is not 123456\n";

    // Each (zone, quantity) block at 100 + 80 × (zone id − 1) + 10 × quantity slot.
    const json zones = sql(db, "SELECT id, name FROM zones WHERE name != '(system)' ORDER BY id");
    for (const auto& z : zones) {
        for (std::size_t q = 0; q < quantities.size(); ++q) {
            Block b;
            b.zone = z.at("name");
            b.quantity = quantities[q];
            b.address = 100 + 80 * (z.at("id").get<int>() - 1) + 10 * static_cast<int>(q);
            const json points = sql(
                db,
                "SELECT e.id, e.acquired, r.value, r.uncertainty, r.significant, "
                "(SELECT accepted FROM registrations g WHERE g.epoch_id = e.id) AS accepted "
                "FROM zone_results r JOIN epochs e ON e.id = r.epoch_id WHERE r.zone_id = " +
                    std::to_string(z.at("id").get<int>()) +
                    " AND r.quantity_id = (SELECT id FROM quantities WHERE name = '" + b.quantity +
                    "') AND e.acquired >= " + std::to_string(last_done - 30 * 86400) +
                    " ORDER BY e.acquired, e.id");
            if (!points.empty()) {
                const json& last = points.back();
                b.value = last.at("value").get<double>();
                if (!last.at("uncertainty").is_null()) b.lod = last.at("uncertainty").get<double>();
                // Least-squares slope over the 24 h up to the latest value, per day.
                std::vector<std::pair<double, double>> w;
                const std::int64_t t_last = last.at("acquired");
                for (const auto& p : points) {
                    if (p.at("acquired").get<std::int64_t>() >= t_last - 86400) {
                        w.emplace_back(
                            static_cast<double>(p.at("acquired").get<std::int64_t>() - t_last),
                            p.at("value").get<double>());
                    }
                }
                if (w.size() >= 2) {
                    double mt = 0, mv = 0;
                    for (const auto& [t, v] : w) mt += t, mv += v;
                    mt /= static_cast<double>(w.size());
                    mv /= static_cast<double>(w.size());
                    double stt = 0, stv = 0;
                    for (const auto& [t, v] : w)
                        stt += (t - mt) * (t - mt), stv += (t - mt) * (v - mv);
                    b.rate = stv / stt * 86400.0;
                }
                b.quality =
                    1 | (static_cast<double>(now - t_last) > stale_seconds ? 2 : 0) |
                    (last.at("significant").get<int>() ? 0 : 4) |
                    (!last.at("accepted").is_null() && last.at("accepted").get<int>() == 0 ? 8 : 0);
            }
            for (const auto& r : rules) {
                if (r.at("zone") != b.zone || r.at("quantity") != b.quantity) continue;
                const int l = level_code(r.at("level")), s = state_code(r.at("state"));
                if (l > b.level || (l == b.level && (s == 1 || s == 3) && b.state != 1)) {
                    b.level = l;
                    b.state = s;
                }
            }
            const auto words = mbpoll_read(port, "3:hex", b.address, 9);
            if (words.empty()) {
                diff << "mbpoll could not read " << b.address << "\n";
                continue;
            }
            const std::string at =
                b.zone + "/" + b.quantity + " [" + std::to_string(b.address) + "]";
            const auto check_float = [&](int off, const std::optional<double>& want,
                                         const char* name, double rel) {
                const float got = float_of(words[static_cast<std::size_t>(off)],
                                           words[static_cast<std::size_t>(off) + 1]);
                if (!want) {
                    if (bits_of(got) != 0x7FC00000u)
                        diff << at << name << " reads " << got << ", want NaN\n";
                } else if (rel == 0 ? got != static_cast<float>(*want)
                                    : std::abs(got - *want) > rel * std::abs(*want) + 1e-12) {
                    diff << at << name << " reads " << got << ", the database says " << *want
                         << "\n";
                }
            };
            check_float(0, b.value, ".value", 0);  // the stored double rounded to float32
            check_float(2, b.lod, ".lod", 0);
            // The daemon sums in another order: a few float ulps.
            check_float(4, b.rate, ".rate", 1e-6);
            const int got_quality = static_cast<int>(words[6]),
                      got_level = static_cast<int>(words[7]),
                      got_state = static_cast<int>(words[8]);
            if (got_quality != b.quality || got_level != b.level || got_state != b.state) {
                diff << at << " quality/level/state read " << got_quality << "/" << got_level << "/"
                     << got_state << ", the database says " << b.quality << "/" << b.level << "/"
                     << b.state << "\n";
            }
        }
    }

    // Discrete inputs: 0 any alarm, 1 any unacknowledged, 2 system fault; per rule
    // 16 + 4 × slot + warning, alert, alarm, unacknowledged.
    const int max_slot = rules.empty() ? 0 : rules.back().at("id").get<int>() - 1;
    const auto bits = mbpoll_read(port, "1", 0, 16 + 4 * (max_slot + 1));
    if (bits.empty()) return diff.str() + "mbpoll could not read the discrete inputs\n";
    const auto expect_bit = [&](int address, bool want, const std::string& name) {
        if ((bits[static_cast<std::size_t>(address)] != 0) != want) {
            diff << name << " (discrete input " << address << ") reads "
                 << bits[static_cast<std::size_t>(address)] << "\n";
        }
    };
    expect_bit(0, any_alarm, "any_alarm");
    expect_bit(1, any_unack, "any_unacknowledged");
    expect_bit(2, false, "system_fault");
    for (const auto& r : rules) {
        const int base = 16 + 4 * (r.at("id").get<int>() - 1);
        const int l = level_code(r.at("level"));
        const std::string name = r.at("name");
        expect_bit(base + 0, l >= 1, name + ".warning");
        expect_bit(base + 1, l >= 2, name + ".alert");
        expect_bit(base + 2, l >= 3, name + ".alarm");
        expect_bit(base + 3, r.at("state") == "unack" || r.at("state") == "rtn_unack",
                   name + ".unacknowledged");
    }
    return diff.str();
}

// ---- `tlsmon query` ---------------------------------------------------------------------

json tlsmon_json(const std::string& args) {
    const auto r = shell(std::string(TLSMON_BINARY) + " " + args + " --format json");
    if (r.status != 0) throw std::runtime_error("tlsmon " + args + ": " + r.output);
    return json::parse(r.output);
}

// A database REAL against the command's number: the same double (both print enough digits).
void expect_same_number(const json& from_tlsmon, const json& from_db, const std::string& what) {
    if (from_db.is_null()) {
        EXPECT_TRUE(from_tlsmon.is_null()) << what << ": " << from_tlsmon;
        return;
    }
    ASSERT_TRUE(from_tlsmon.is_number()) << what << ": " << from_tlsmon;
    EXPECT_EQ(from_tlsmon.get<double>(), from_db.get<double>()) << what;
}

constexpr const char* kUtc = "strftime('%Y-%m-%dT%H:%M:%SZ', %s, 'unixepoch')";
std::string utc(const std::string& column) {
    std::string s = kUtc;
    return s.replace(s.find("%s"), 2, column);
}

// A CSV file's rows as maps of its header's names to the fields.
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& file) {
    std::istringstream in(read_text(file));
    std::string line;
    std::vector<std::string> names;
    std::getline(in, line);
    for (std::istringstream h(line); std::getline(h, line, ',');) names.push_back(line);
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        std::map<std::string, std::string> row;
        std::istringstream fields(line);
        for (const auto& name : names) {
            std::string f;
            std::getline(fields, f, ',');
            row[name] = f;
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

// The one-shot commands on the two scan files of the reference epoch and of epoch `k`, with
// the daemon's configuration, give what the daemon stored for epoch k: every core point's
// M3C2 distance and LoD95 (stored as float32), and every zone's keypoint vector (the
// command's --summary, full precision) from the matches its per-match CSV lists as kept.
void one_shot_commands_reproduce_the_daemon(const Scenario& s, int k, std::int64_t epoch_id,
                                            const fs::path& config, const fs::path& db,
                                            const fs::path& dir) {
    const auto scan = [&](int i) {
        return (s.scans() / (s.stems.at(static_cast<std::size_t>(i)) + ".ptx")).string();
    };
    const std::string pair = scan(0) + " " + scan(k) + " --config " + config.string();
    const auto m3c2 = shell(std::string(TLSMON_BINARY) + " m3c2 " + pair + " --out " +
                            (dir / "m3c2.csv").string());
    ASSERT_EQ(m3c2.status, 0) << m3c2.output;
    const json stored = tlsmon_json("query corepoints --epoch " + std::to_string(epoch_id) +
                                    " --config " + config.string());
    const auto rows = csv_rows(dir / "m3c2.csv");
    ASSERT_EQ(rows.size(), stored.size());
    int with_distance = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const json& d = stored[i].at("distance");
        if (rows[i].at("distance_m").empty()) {
            EXPECT_TRUE(d.is_null()) << "core point " << i;
            continue;
        }
        ASSERT_FALSE(d.is_null()) << "core point " << i;
        const double one_shot = std::stod(rows[i].at("distance_m"));
        EXPECT_NEAR(one_shot, d.get<double>(), 2e-9 + 1e-7 * std::abs(one_shot)) << i;
        const double lod = std::stod(rows[i].at("lod95_m"));
        EXPECT_NEAR(lod, stored[i].at("lod95").get<double>(), 2e-9 + 1e-7 * lod) << i;
        EXPECT_NEAR(std::stod(rows[i].at("x_m")), stored[i].at("x").get<double>(), 1e-12) << i;
        ++with_distance;
    }
    EXPECT_GT(with_distance, 100);

    // Patch-based M3C2: each zone's count of the CSV's patch distances is the stored row's n,
    // and the median the command prints (over the zone's area, to the last bit) its value.
    const auto pbm3c2 = shell(std::string(TLSMON_BINARY) + " pbm3c2 " + pair + " --out " +
                              (dir / "pbm3c2.csv").string());
    ASSERT_EQ(pbm3c2.status, 0) << pbm3c2.output;
    std::map<std::string, std::vector<double>> patch_distances;
    for (const auto& row : csv_rows(dir / "pbm3c2.csv")) {
        if (row.at("distance_m").empty()) continue;
        std::stringstream zones(row.at("zones"));
        for (std::string zone; std::getline(zones, zone, ';');)
            patch_distances[zone].push_back(std::stod(row.at("distance_m")));
    }
    int pb_zones = 0;
    for (const auto& row :
         sql(db,
             "SELECT z.name AS zone, r.value, r.n FROM zone_results r JOIN zones z ON z.id = "
             "r.zone_id JOIN quantities q ON q.id = r.quantity_id WHERE r.epoch_id = " +
                 std::to_string(epoch_id) + " AND q.name = 'pbm3c2_median_m'")) {
        const auto zone = row.at("zone").get<std::string>();
        ASSERT_EQ(static_cast<std::int64_t>(patch_distances[zone].size()),
                  row.at("n").get<std::int64_t>())
            << row.dump();
        const std::string printed = "\n" + zone + " pbm3c2_median_m = ";
        const auto at = pbm3c2.output.find(printed);
        ASSERT_NE(at, std::string::npos) << pbm3c2.output;
        EXPECT_EQ(std::stod(pbm3c2.output.substr(at + printed.size())),
                  row.at("value").get<double>())
            << row.dump();
        ++pb_zones;
    }
    // The south face at least: the grazing west face holds few patches of plane (docs/pbm3c2.md).
    EXPECT_GE(pb_zones, 1);

    // `tlsmon export --map pbm3c2`: every patch where its distance was taken, with the stored
    // distance and LoD (float32 of the one-shot's), NaN where none; read back by tlsmon and by
    // copc.js. A patch compared in part is placed by its float32 shift from its centre.
    const fs::path las = dir / "pbm3c2.las";
    const auto exported =
        shell(std::string(TLSMON_BINARY) + " export --map pbm3c2 --epoch " +
              std::to_string(epoch_id) + " --out " + las.string() + " --config " + config.string());
    ASSERT_EQ(exported.status, 0) << exported.output;
    const auto patches = csv_rows(dir / "pbm3c2.csv");
    const LasPoints own = read_las_points(las);
    const json other = read_las_independently(las);
    ASSERT_EQ(own.xyz.size(), patches.size());
    ASSERT_EQ(own.attributes.at(0).name, "pbm3c2_distance_m");
    ASSERT_EQ(own.attributes.at(1).name, "pbm3c2_lod95_m");
    int compared_in_part = 0;
    for (const auto& row : patches) compared_in_part += row.at("compared") == "part";
    // Whether the scene's epoch 5 has a patch compared in part depends on the date the scenario
    // starts (the sun's path bends the pier): 1 of 649 on some days, none on others. Where one
    // is, its float32 shift is checked below; tests/pipeline/test_pbm3c2_place.cpp checks the
    // placement on a patch seen in part by construction.
    std::printf("pbm3c2: %zu patches, %d compared in part\n", patches.size(), compared_in_part);
    for (std::size_t k = 0; k < patches.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            const double x = std::stod(patches[k].at(std::string(1, "xyz"[c]) + "_m"));
            EXPECT_NEAR(own.xyz[k][c], x, 0.5e-6 + 1e-7) << k;
            EXPECT_NEAR(other.at("points").at(std::string(1, "XYZ"[c]))[k].get<double>(), x,
                        0.5e-6 + 1e-7);
        }
        for (const auto& [column, a] : {std::pair{"distance_m", 0}, std::pair{"lod95_m", 1}}) {
            const auto& attribute = own.attributes[std::size_t(a)];
            const double value = attribute.values[k];
            const double theirs = las_number(other.at("points").at(attribute.name)[k]);
            if (patches[k].at(column).empty()) {
                EXPECT_TRUE(std::isnan(value) && std::isnan(theirs)) << k;
                continue;
            }
            const double one_shot = std::stod(patches[k].at(column));
            EXPECT_NEAR(value, one_shot, 2e-9 + 1e-7 * std::abs(one_shot)) << column << " " << k;
            EXPECT_EQ(theirs, value) << column << " " << k;
        }
    }

    const auto keypoints =
        shell(std::string(TLSMON_BINARY) + " keypoints " + pair + " --out " +
              (dir / "keypoints.csv").string() + " --summary " + (dir / "segments.csv").string());
    ASSERT_EQ(keypoints.status, 0) << keypoints.output;
    // Each zone's kept matches (the per-match file) and figures (the summary).
    std::map<std::string, int> kept;
    for (const auto& m : csv_rows(dir / "keypoints.csv"))
        if (m.at("removed_by").empty()) ++kept[m.at("zone")];
    std::map<std::string, std::map<std::string, std::string>> summary;
    for (const auto& row : csv_rows(dir / "segments.csv")) summary[row.at("zone")] = row;
    int zones = 0;
    for (const auto& row :
         sql(db,
             "SELECT z.name AS zone, q.name AS quantity, r.value, r.n FROM zone_results r "
             "JOIN zones z ON z.id = r.zone_id JOIN quantities q ON q.id = r.quantity_id "
             "WHERE r.epoch_id = " +
                 std::to_string(epoch_id) +
                 " AND q.name IN ('keypoint_dx_m', 'keypoint_dy_m', 'keypoint_dz_m')")) {
        const std::string zone = row.at("zone");
        const std::string quantity = row.at("quantity");
        ASSERT_TRUE(kept.count(zone) && summary.count(zone)) << zone;
        EXPECT_EQ(row.at("n").get<int>(), kept[zone]) << zone;
        EXPECT_EQ(std::stoi(summary[zone].at("kept")), kept[zone]) << zone;
        EXPECT_NEAR(std::stod(summary[zone].at(quantity.substr(9))), row.at("value").get<double>(),
                    1e-12)
            << zone << " " << quantity;
        zones += quantity == "keypoint_dx_m";
    }
    EXPECT_GE(zones, 2);
}

TEST(EndToEnd, DemoScenarioFromScanFileToModbusRegisterAgainstTheTruth) {
    const auto t0 = Clock::now();
    const TempDir tmp("e2e");
    const Scenario s = shared_scenario(kEpochs, next_midnight());
    ASSERT_EQ(s.truth.size(), static_cast<std::size_t>(kEpochs));
    const double render_s = seconds_since(t0);
    const int step_epoch = s.scene.step_epoch, knocked_epoch = s.scene.knocked_epoch;
    ASSERT_EQ(step_epoch, 12);
    ASSERT_EQ(knocked_epoch, 6);

    // The truth as read here reproduces the simulator's own sample displacements.
    for (const auto& t : s.truth) {
        for (const auto& sample : t.doc.at("samples")) {
            const auto& p = sample.at("point");
            const auto& d = sample.at("displacement");
            const Eigen::Vector3d u =
                t.displacement({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
            EXPECT_LT((u - Eigen::Vector3d(d[0], d[1], d[2])).norm(), 1e-12)
                << "epoch " << t.epoch << " " << sample.at("name");
        }
    }

    const int port = free_tcp_port();
    const fs::path run = tmp.path() / "run";
    const fs::path config = write_config(s, run, port);
    const fs::path db = run / "tlsmon.sqlite";
    const fs::path log = run / "daemon.log";
    const std::string on_config = " --config " + config.string();
    DaemonProcess daemon(config, log);
    ASSERT_TRUE(wait_until([&] { return mbpoll_read(port, "3", 0, 1).size() == 1; }, 30))
        << read_text(log);
    const std::vector<std::uint32_t> heartbeat0 = mbpoll_read(port, "3", 1, 1);
    const auto heartbeat0_at = Clock::now();

    // One epoch at a time; after the step alarm is raised, SCADA acknowledges it.
    std::optional<int> acknowledged_after;
    int south_top_slot = -1;
    const auto run_start = Clock::now();
    for (int k = 0; k < kEpochs; ++k) {
        feed(s, k, run / "ingest");
        ASSERT_TRUE(wait_until([&] { return processed(db) == k + 1; }, 90)) << "epoch " << k << "\n"
                                                                            << read_text(log);
        if (acknowledged_after) continue;
        const json state =
            sql(db,
                "SELECT r.id, coalesce(s.state, 'normal') AS state FROM alarm_rules r "
                "LEFT JOIN alarm_states s ON s.rule_id = r.id WHERE r.name = '" +
                    std::string(kStepRule) + "'");
        ASSERT_EQ(state.size(), 1u);
        if (state.at(0).at("state") != "unack") continue;
        south_top_slot = state.at(0).at("id").get<int>() - 1;
        const int bit = 16 + 4 * south_top_slot;
        // The raised alarm shows: its alarm and unacknowledged bits (within a snapshot).
        ASSERT_TRUE(wait_until(
            [&] {
                const auto b = mbpoll_read(port, "1", bit, 4);
                return b == std::vector<std::uint32_t>{1, 1, 1, 1};
            },
            10))
            << "the step rule's bits after its raise at epoch " << k;
        const std::string coil = std::to_string(16 + south_top_slot);
        const auto write = shell("timeout 10 mbpoll -m tcp -a 1 -p " + std::to_string(port) +
                                 " -0 -1 -t 0 -r " + coil + " 127.0.0.1 1");
        ASSERT_EQ(write.status, 0) << write.output;
        ASSERT_TRUE(wait_until(
            [&] {
                return sql(db,
                           "SELECT 1 FROM alarm_states s JOIN alarm_rules r ON r.id = s.rule_id "
                           "WHERE r.name = '" +
                               std::string(kStepRule) +
                               "' AND s.state = 'ack' AND EXISTS (SELECT 1 FROM alarm_events e "
                               "WHERE e.rule_id = r.id AND e.kind = 'ack' AND e.actor LIKE 'SCADA "
                               "modbus client 127.0.0.1:%')")
                           .size() == 1;
            },
            10))
            << "the acknowledgement written to coil " << coil << " is not in the database";
        ASSERT_TRUE(wait_until(
            [&] { return mbpoll_read(port, "1", bit + 3, 1) == std::vector<std::uint32_t>{0}; },
            10))
            << "the unacknowledged bit did not clear";
        acknowledged_after = k;
    }
    const double run_s = seconds_since(run_start);
    ASSERT_TRUE(acknowledged_after.has_value()) << "the step alarm was never raised";

    // Every register equals the database (the snapshot follows within a second or so).
    std::string mismatch;
    const bool registers_agree = wait_until(
        [&] {
            mismatch = compare_registers(
                port, db, {"m3c2_median_m", "m3c2_mean_m", "keypoint_dz_m"}, 2 * 86400.0);
            return mismatch.empty();
        },
        15);
    EXPECT_TRUE(registers_agree) << mismatch;
    const std::vector<std::uint32_t> heartbeat1 = mbpoll_read(port, "3", 1, 1);
    ASSERT_EQ(heartbeat0.size(), 1u);
    ASSERT_EQ(heartbeat1.size(), 1u);
    const double beat_s = seconds_since(heartbeat0_at);
    const int beats = static_cast<int>((heartbeat1[0] - heartbeat0[0]) & 0xFFFF);
    EXPECT_NEAR(beats, beat_s, 2.0) << "heartbeat: +1 per second";

    // `tlsmon query`, `tlsmon alarms history` and the database, read while the daemon runs.
    {
        SCOPED_TRACE("tlsmon query epochs");
        const json out = tlsmon_json("query epochs" + on_config);
        const json rows = sql(db, "SELECT id, " + utc("acquired") +
                                      " AS acquired, status, point_count, file_size, sha256, "
                                      "reason FROM epochs ORDER BY acquired, id");
        ASSERT_EQ(out.size(), rows.size());
        ASSERT_EQ(rows.size(), static_cast<std::size_t>(kEpochs));
        for (std::size_t i = 0; i < rows.size(); ++i) {
            EXPECT_EQ(out[i].at("epoch"), rows[i].at("id"));
            EXPECT_EQ(out[i].at("acquired"), rows[i].at("acquired"));
            EXPECT_EQ(out[i].at("status"), rows[i].at("status"));
            EXPECT_EQ(out[i].at("points"), rows[i].at("point_count"));
            EXPECT_EQ(out[i].at("size"), rows[i].at("file_size"));
            EXPECT_EQ(out[i].at("sha256"), rows[i].at("sha256"));
            EXPECT_EQ(out[i].at("reason"), rows[i].at("reason"));
        }
    }
    int series_compared = 0;
    for (const auto& zq : sql(db,
                              "SELECT DISTINCT z.name AS zone, q.name AS quantity FROM "
                              "zone_results r JOIN zones z ON z.id = r.zone_id JOIN quantities "
                              "q ON q.id = r.quantity_id ORDER BY z.name, q.name")) {
        const std::string zone = zq.at("zone"), quantity = zq.at("quantity");
        SCOPED_TRACE("tlsmon query series " + zone + " " + quantity);
        const json out =
            tlsmon_json("query series --zone " + zone + " --quantity " + quantity + on_config);
        const json rows = sql(
            db, "SELECT r.epoch_id, " + utc("e.acquired") +
                    " AS acquired, r.value, r.uncertainty, r.n, r.significant FROM zone_results r "
                    "JOIN epochs e ON e.id = r.epoch_id WHERE r.zone_id = (SELECT id FROM zones "
                    "WHERE name = '" +
                    zone +
                    "') AND r.quantity_id = (SELECT id FROM quantities "
                    "WHERE name = '" +
                    quantity + "') ORDER BY e.acquired, e.id");
        ASSERT_EQ(out.size(), rows.size());
        for (std::size_t i = 0; i < rows.size(); ++i) {
            EXPECT_EQ(out[i].at("epoch"), rows[i].at("epoch_id"));
            EXPECT_EQ(out[i].at("acquired"), rows[i].at("acquired"));
            expect_same_number(out[i].at("value"), rows[i].at("value"), "value");
            expect_same_number(out[i].at("uncertainty"), rows[i].at("uncertainty"), "uncertainty");
            EXPECT_EQ(out[i].at("n"), rows[i].at("n"));
            EXPECT_EQ(out[i].at("significant").get<bool>(), rows[i].at("significant") == 1);
        }
        ++series_compared;
    }
    EXPECT_GE(series_compared, 3 * 4) << "three zones with M3C2's quantities";
    {
        SCOPED_TRACE("tlsmon alarms history");
        const json out = tlsmon_json("alarms history" + on_config);
        const json rows = sql(db, "SELECT " + utc("e.time") +
                                      " AS time, r.name AS rule, e.kind, e.level, e.value, "
                                      "e.epoch_id, e.actor, e.message FROM alarm_events e JOIN "
                                      "alarm_rules r ON r.id = e.rule_id ORDER BY e.time, e.id");
        ASSERT_EQ(out.size(), rows.size());
        for (std::size_t i = 0; i < rows.size(); ++i) {
            for (const char* k : {"time", "rule", "kind", "level", "actor", "message"}) {
                EXPECT_EQ(out[i].at(k), rows[i].at(k)) << k;
            }
            expect_same_number(out[i].at("value"), rows[i].at("value"), "value");
            EXPECT_EQ(out[i].at("epoch"), rows[i].at("epoch_id"));
        }
    }
    {
        SCOPED_TRACE("tlsmon query registrations");
        const json out = tlsmon_json("query registrations" + on_config);
        const json rows =
            sql(db,
                "SELECT g.epoch_id, g.status, g.accepted, g.method, g.target_count, "
                "g.rms_m, g.omega_rad, g.phi_rad, g.kappa_rad, g.tx_m, g.ty_m, g.tz_m, "
                "g.sigma_omega_rad, g.sigma_phi_rad, g.sigma_kappa_rad, g.sigma_tx_m, "
                "g.sigma_ty_m, g.sigma_tz_m, g.qw, g.qx, g.qy, g.qz, "
                "g.variance_factor, g.redundancy, g.reason, e.status AS "
                "epoch_status FROM registrations g JOIN "
                "epochs e ON e.id = g.epoch_id ORDER BY e.acquired, e.id");
        ASSERT_EQ(out.size(), rows.size());
        const double arcsec = 180.0 * 3600.0 / 3.141592653589793;
        const std::vector<std::pair<const char*, const char*>> scaled = {
            {"omega_arcsec", "omega_rad"},
            {"phi_arcsec", "phi_rad"},
            {"kappa_arcsec", "kappa_rad"},
            {"sigma_omega_arcsec", "sigma_omega_rad"},
            {"sigma_phi_arcsec", "sigma_phi_rad"},
            {"sigma_kappa_arcsec", "sigma_kappa_rad"},
            {"tx_m", "tx_m"},
            {"ty_m", "ty_m"},
            {"tz_m", "tz_m"},
            {"sigma_tx_m", "sigma_tx_m"},
            {"sigma_ty_m", "sigma_ty_m"},
            {"sigma_tz_m", "sigma_tz_m"},
            {"rms_m", "rms_m"}};
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const json& o = out[i];
            const json& r = rows[i];
            EXPECT_EQ(o.at("epoch"), r.at("epoch_id"));
            EXPECT_EQ(o.at("status"), r.at("epoch_status"));
            EXPECT_EQ(o.at("registration"), r.at("status"));
            EXPECT_EQ(o.at("accepted").get<bool>(), r.at("accepted") == 1);
            EXPECT_EQ(o.at("method"), r.at("method"));
            EXPECT_EQ(o.at("targets_used"), r.at("target_count"));
            EXPECT_EQ(o.at("redundancy"), r.at("redundancy"));
            EXPECT_EQ(o.at("reason"), r.at("reason"));
            for (const char* q : {"qw", "qx", "qy", "qz", "variance_factor"}) {
                expect_same_number(o.at(q), r.at(q), q);
            }
            for (const auto& [shown, stored] : scaled) {
                if (r.at(stored).is_null()) {
                    EXPECT_TRUE(o.at(shown).is_null()) << shown;
                    continue;
                }
                const double unit =
                    std::string(shown).find("arcsec") != std::string::npos ? arcsec : 1.0;
                EXPECT_DOUBLE_EQ(o.at(shown).get<double>(), r.at(stored).get<double>() * unit)
                    << shown << " epoch " << r.at("epoch_id");
            }
            // Each target's name and use, as stored.
            for (const auto& t : sql(db,
                                     "SELECT target, use, status FROM target_observations "
                                     "WHERE epoch_id = " +
                                         r.at("epoch_id").dump())) {
                const std::string use = t.at("use").get<std::string>().empty()
                                            ? t.at("status").get<std::string>()
                                            : t.at("use").get<std::string>();
                const json& listed = o.at("targets");
                EXPECT_TRUE(std::any_of(listed.begin(), listed.end(), [&](const json& l) {
                    return l.at("target") == t.at("target") && l.at("use") == use;
                })) << listed;
            }
        }
    }

    daemon.signal(SIGTERM);
    ASSERT_EQ(daemon.wait(30), 0) << read_text(log);

    // ---- Against the truth ------------------------------------------------------------
    const json epochs = sql(db, "SELECT id, acquired, status FROM epochs ORDER BY acquired, id");
    ASSERT_EQ(epochs.size(), static_cast<std::size_t>(kEpochs));
    std::map<std::int64_t, int> index_of;  // epoch id -> truth epoch
    for (int i = 0; i < kEpochs; ++i) {
        const json& e = epochs[static_cast<std::size_t>(i)];
        EXPECT_EQ(e.at("acquired").get<std::int64_t>(), s.truth[static_cast<std::size_t>(i)].time);
        EXPECT_EQ(e.at("status"), "done") << "epoch " << i;
        index_of[e.at("id").get<std::int64_t>()] = i;
    }

    // Registration (issue 10): the stored transformation maps a point of epoch i's scanner
    // frame q to the reference's frame; exactly, that is H₀⁻¹·Hᵢ·q. At the truth's pier points:
    // ≤ 1 mm RMS in every epoch, and within the predicted 2σ (the largest zone 3-D σ the
    // registration stored) in at least 90 % of the epochs.
    const Eigen::Affine3d h0 = s.truth[0].header_to_true;
    int within_2sigma = 0, registered = 0;
    double worst_rms = 0;
    for (int i = 1; i < kEpochs; ++i) {
        const auto id = epochs[static_cast<std::size_t>(i)].at("id").dump();
        const json reg = sql(db,
                             "SELECT hex(transform) AS m, accepted, (SELECT max(max_sigma_3d_m) "
                             "FROM registration_zone_sigmas z WHERE z.epoch_id = g.epoch_id) AS "
                             "sigma FROM registrations g WHERE epoch_id = " +
                                 id);
        ASSERT_EQ(reg.size(), 1u) << "epoch " << i;
        EXPECT_EQ(reg[0].at("accepted"), 1) << "epoch " << i;
        const std::string hex = reg[0].at("m");
        ASSERT_EQ(hex.size(), 256u);
        Eigen::Matrix4d m;
        for (int k = 0; k < 16; ++k) {
            std::uint64_t bits = 0;
            for (int b = 0; b < 8; ++b) {  // float64 little-endian
                bits |= std::stoull(hex.substr(static_cast<std::size_t>(16 * k + 2 * b), 2),
                                    nullptr, 16)
                        << (8 * b);
            }
            double v;
            std::memcpy(&v, &bits, sizeof v);
            m(k / 4, k % 4) = v;
        }
        const Truth& t = s.truth[static_cast<std::size_t>(i)];
        const Eigen::Affine3d exact = h0.inverse() * t.header_to_true;
        double sum2 = 0, top_error = 0;
        int n = 0;
        for (const auto& sample : t.doc.at("samples")) {
            const auto& p = sample.at("point");
            const Eigen::Vector3d q =
                t.header_to_true.inverse() *
                Eigen::Vector3d(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
            const double e = (Eigen::Affine3d(m) * q - exact * q).norm();
            sum2 += e * e;
            ++n;
            if (sample.at("name") == "top_centre") top_error = e;
        }
        const double rms = std::sqrt(sum2 / n);
        worst_rms = std::max(worst_rms, rms);
        EXPECT_LE(rms, 0.001) << "epoch " << i << ": registration error at the pier";
        ++registered;
        within_2sigma += top_error <= 2.0 * reg[0].at("sigma").get<double>();
        // The knocked target is out from the epoch it moved on; no other target ever.
        for (const auto& o : sql(db,
                                 "SELECT target, use, status FROM target_observations WHERE "
                                 "epoch_id = " +
                                     id)) {
            const bool out = o.at("use") == "excluded_outlier" || o.at("status") == "excluded";
            EXPECT_EQ(out, o.at("target") == s.scene.knocked_target && i >= knocked_epoch)
                << "epoch " << i << " " << o.at("target") << " " << o.at("use");
        }
    }
    EXPECT_GE(within_2sigma, static_cast<int>(std::ceil(0.9 * registered)))
        << within_2sigma << " of " << registered << " epochs within 2σ";

    // M3C2 (issue 11): per zone, the median against the true change along the face's normal
    // (towards the scanner) since the reference epoch — the median of n·(uᵢ − u₀) over the
    // face's heights in the zone (the field does not vary along a face's width). Bound: 0.5 mm
    // RMS for the zones on the south face, which faces the scanner; the west face, seen at 87°,
    // is reported only.
    struct ZoneOnFace {
        std::string name;
        Eigen::Vector3d normal, at;  // a point of the face at z = 0
        double z0, z1;
        bool faces_scanner;
    };
    const json& pier = s.truth.back().doc.at("pier");
    const double x0 = pier.at("x0"), y0 = pier.at("y0"), y1 = pier.at("y1"), x1 = pier.at("x1");
    const std::vector<ZoneOnFace> zones = {
        {"pier_south_face", {0, -1, 0}, {0.5 * (x0 + x1), y0, 0}, 0, 40, true},
        {std::string(kStepZone), {0, -1, 0}, {0.5 * (x0 + x1), y0, 0}, 30, 40, true},
        {"pier_west_face", {-1, 0, 0}, {x0, 0.5 * (y0 + y1), 0}, 0, 40, false}};
    std::cout << "M3C2 zone median - truth (mm):\n";
    for (const auto& z : zones) {
        const json rows = sql(db,
                              "SELECT r.epoch_id, r.value FROM zone_results r WHERE r.zone_id "
                              "= (SELECT id FROM zones WHERE name = '" +
                                  z.name +
                                  "') AND r.quantity_id = (SELECT id FROM quantities WHERE "
                                  "name = 'm3c2_median_m')");
        ASSERT_EQ(rows.size(), static_cast<std::size_t>(kEpochs)) << z.name;
        double sum2 = 0, worst = 0;
        for (const auto& r : rows) {
            const int i = index_of.at(r.at("epoch_id").get<std::int64_t>());
            std::vector<double> change;
            for (int k = 0; k <= 2000; ++k) {
                Eigen::Vector3d p = z.at;
                p.z() = z.z0 + (z.z1 - z.z0) * k / 2000.0;
                change.push_back(z.normal.dot(s.truth[static_cast<std::size_t>(i)].displacement(p) -
                                              s.truth[0].displacement(p)));
            }
            std::nth_element(change.begin(), change.begin() + 1000, change.end());
            const double e = r.at("value").get<double>() - change[1000];
            sum2 += e * e;
            worst = std::max(worst, std::abs(e));
        }
        const double rms = std::sqrt(sum2 / kEpochs);
        std::cout << "  " << z.name << ": RMS " << 1e3 * rms << ", max " << 1e3 * worst << "\n";
        if (z.faces_scanner) {
            EXPECT_LE(rms, 0.0005) << z.name;
        }
    }

    // Keypoints (issue 12): the overview's 0.05° samples the pier every 39 mm, coarser than
    // keypoints.max_sample_spacing; the scene's detail strip at 0.012° (9–13 mm) measures the
    // south face and its top band. Truth along the wall (h = +x, v = +z for the south face)
    // at the zone's stored keypoint_height_m, the mean height of its kept matches: u_x grows
    // as z², so over the face's 40 m the mean of u differs from u at the mean height by
    // var(z)/H² of the top's (≈ 8 %, a fraction of a millimetre); over the top band's 10 m by
    // 0.5 %. The grazing west face stays undefined. Bound: issue 12's 1.0 mm RMS.
    {
        const auto series = [&](const std::string& zone, const std::string& quantity) {
            std::map<int, double> out;
            for (const auto& r : sql(db,
                                     "SELECT r.epoch_id, r.value FROM zone_results r WHERE "
                                     "r.zone_id = (SELECT id FROM zones WHERE name = '" +
                                         zone +
                                         "') AND r.quantity_id = (SELECT id FROM quantities "
                                         "WHERE name = '" +
                                         quantity + "')")) {
                out[index_of.at(r.at("epoch_id").get<std::int64_t>())] =
                    r.at("value").get<double>();
            }
            return out;
        };
        for (const std::string& zone : {std::string("pier_south_face"), std::string(kStepZone)}) {
            const auto height = series(zone, "keypoint_height_m");
            const auto h = series(zone, "keypoint_along_surface_h_m");
            const auto v = series(zone, "keypoint_along_surface_v_m");
            EXPECT_EQ(h.size(), static_cast<std::size_t>(kEpochs)) << zone << ": undefined epochs";
            double sum2_h = 0, sum2_v = 0, worst = 0;
            for (const auto& [i, value] : h) {
                const Eigen::Vector3d p(0.5 * (x0 + x1), y0, height.at(i));
                const Eigen::Vector3d u = s.truth[static_cast<std::size_t>(i)].displacement(p) -
                                          s.truth[0].displacement(p);
                const double eh = value - u.x(), ev = v.at(i) - u.z();
                sum2_h += eh * eh;
                sum2_v += ev * ev;
                worst = std::max({worst, std::abs(eh), std::abs(ev)});
            }
            const double n = std::max<double>(1, static_cast<double>(h.size()));
            const double rms_h = std::sqrt(sum2_h / n), rms_v = std::sqrt(sum2_v / n);
            std::cout << "keypoints " << zone << " - truth along the surface (mm): h RMS "
                      << 1e3 * rms_h << ", v RMS " << 1e3 * rms_v << ", max " << 1e3 * worst
                      << "\n";
            EXPECT_LE(rms_h, 0.001) << zone;
            EXPECT_LE(rms_v, 0.001) << zone;
        }
        EXPECT_TRUE(series("pier_west_face", "keypoint_along_surface_h_m").empty())
            << "a keypoint displacement on the grazing west face";
        EXPECT_EQ(series("pier_west_face", "keypoint_count").size(),
                  static_cast<std::size_t>(kEpochs));
    }

    // Alarms: the step rule raises within on_delay + 1 epochs of the step, never before it;
    // no other rule raises. No system alarm either: the knocked target is excluded and the
    // epochs keep four targets (accepted, so no system.registration_rejected); no epoch fails;
    // the acquisition times run from the next midnight on, ahead of the wall clock, so
    // system.stale (no new epoch for 3 × 15 min of wall time) has no cause.
    const int on_delay = 1;  // demo_daemon_config
    std::optional<int> raised_at;
    int acks = 0;
    for (const auto& e : sql(db,
                             "SELECT r.name, e.kind, e.level, e.epoch_id, e.actor FROM "
                             "alarm_events e JOIN alarm_rules r ON r.id = e.rule_id ORDER BY "
                             "e.time, e.id")) {
        const std::string rule = e.at("name");
        EXPECT_EQ(rule, std::string(kStepRule)) << e.dump();
        if (rule != kStepRule) continue;
        if (e.at("kind") == "raise") {
            EXPECT_FALSE(raised_at.has_value()) << "raised twice: " << e.dump();
            raised_at = index_of.at(e.at("epoch_id").get<std::int64_t>());
        } else if (e.at("kind") == "ack") {
            // Who acknowledged: the Modbus client's address, not only "SCADA".
            EXPECT_EQ(e.at("actor").get<std::string>().rfind("SCADA modbus client 127.0.0.1:", 0),
                      0u)
                << e.dump();
            ++acks;
        } else {
            ADD_FAILURE() << "unexpected event " << e.dump();
        }
    }
    ASSERT_TRUE(raised_at.has_value());
    EXPECT_GE(*raised_at, step_epoch);
    EXPECT_LE(*raised_at, step_epoch + on_delay + 1);
    EXPECT_EQ(acks, 1);
    EXPECT_EQ(*acknowledged_after, *raised_at);
    const json final_state = sql(db,
                                 "SELECT s.state, s.level FROM alarm_states s JOIN "
                                 "alarm_rules r ON r.id = s.rule_id WHERE r.name = '" +
                                     std::string(kStepRule) + "'");
    ASSERT_EQ(final_state.size(), 1u);
    EXPECT_EQ(final_state[0].at("state"), "ack") << "latched, the band still stepped";
    EXPECT_EQ(final_state[0].at("level"), "alarm");

    // The one-shot commands measure as the stages do (epoch 5: before the knocked target).
    for (const auto& [id, i] : index_of) {
        if (i != 5) continue;
        SCOPED_TRACE("tlsmon m3c2 / pbm3c2 / keypoints --config on epoch 5");
        one_shot_commands_reproduce_the_daemon(s, 5, id, config, db, tmp.path());
    }

    std::cout << "end to end: " << kEpochs << " epochs; rendered or read in " << render_s
              << " s, processed and checked in " << run_s << " s, " << seconds_since(t0)
              << " s in all; registration worst RMS at the pier " << 1e3 * worst_rms << " mm, "
              << within_2sigma << "/" << registered << " within 2σ; step raised at " << *raised_at
              << " (step " << step_epoch << ")\n";
}

}  // namespace
}  // namespace tlsmon::test::e2e
