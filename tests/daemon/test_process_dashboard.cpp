// The dashboard in a real browser (issue 26): Debian's chromium, headless, driven through
// chromium-driver by tests/web/dashboard_browser.py, over a daemon fed the demo's scenario
// (the `small` scene, 8 epochs: target knocked at epoch 2, the south face's top band
// stepped 25 mm at epoch 4, so its rule is raised). What each page shows is read from the
// page (its DOM and its chart's own data) and compared with the database read by the
// sqlite3 program, not through tlsmon's storage code:
//   - overview: every zone quantity's latest value and epoch, the last epoch, the active
//     alarms; then, left open, it shows the next epoch by itself when it commits;
//   - zone page: the chart holds exactly the database's points of the quantity;
//   - epoch view: one map mark per core point with a distance;
//   - alarms and events pages: every rule's state, every event;
//   - an operator logs in on the alarms page and acknowledges the step's alarm with a
//     comment: the database's state and history name the user, the Modbus unacknowledged
//     bit (read with mbpoll) clears; a viewer's, an anonymous and a CSRF-less request are
//     refused (403, 401, 403) and change nothing;
//   - no console error on any page; a screenshot of each in build/test-artifacts/dashboard.
// And the server under hostile requests (path traversal in its encoded forms, a 1 MB header,
// methods that would write, malformed parameters and JSON, 100 wrong passwords while an
// epoch commits), each refused while the daemon goes on.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <future>
#include <map>
#include <set>

#include "demo/site_config_writer.hpp"
#include "simulator/scene_file.hpp"
#include "tests/support/dashboard_browser.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/modbus_client.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test::e2e {
namespace {

constexpr int kEpochs = 8;

fs::path artifacts() {
    return browser_artifacts("dashboard");
}

// HTTP status and body of `curl` on `path` (as is: no normalisation of /../).
struct Answer {
    int status = 0;
    std::string body;
};
Answer curl(int port, const std::string& path, const std::string& options = "") {
    const auto r = shell("curl -s --path-as-is -m 10 -w '\\n%{http_code}' " + options + " " +
                         quoted("http://127.0.0.1:" + std::to_string(port) + path));
    Answer a;
    const auto cut = r.output.find_last_of('\n');
    if (cut == std::string::npos) return a;
    a.body = r.output.substr(0, cut);
    a.status = std::atoi(r.output.c_str() + cut + 1);
    return a;
}

// One raw request on a fresh connection; the first line of the answer ("" when the server
// closed without one).
std::string raw_request(int port, const std::string& request) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        ::close(fd);
        return "connect failed";
    }
    timeval tv{10, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::size_t sent = 0;
    while (sent < request.size()) {
        const auto n = ::send(fd, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;  // the server may stop reading and close: that is a refusal too
        sent += static_cast<std::size_t>(n);
    }
    char buf[512];
    const auto n = ::recv(fd, buf, sizeof buf - 1, 0);
    ::close(fd);
    if (n <= 0) return "";
    const std::string answer(buf, static_cast<std::size_t>(n));
    return answer.substr(0, answer.find("\r\n"));
}

// The float32 values of one core point array, decoded from the hex of its blob.
std::vector<float> core_point_array(const fs::path& db, std::int64_t epoch, const char* quantity) {
    const json rows = sql(db, "SELECT hex(data) AS h FROM core_point_arrays WHERE epoch_id = " +
                                  std::to_string(epoch) + " AND quantity = '" + quantity + "'");
    std::vector<float> out;
    if (rows.empty()) return out;
    const std::string hex = rows.at(0).at("h");
    std::vector<unsigned char> bytes;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
        bytes.push_back(static_cast<unsigned char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    out.resize(bytes.size() / 4);
    std::memcpy(out.data(), bytes.data(), out.size() * 4);  // little-endian, as x86 stores it
    return out;
}

json browser(const std::string& arguments) {
    return dashboard_browser(arguments, artifacts());
}

TEST(Dashboard, RealBrowserShowsTheDatabaseAndTheNextEpochByItself) {
    TempDir tmp("dashboard");
    const Scenario s = render_scenario(tmp.path() / "scenario", kEpochs, next_midnight());
    const fs::path run = tmp.path() / "run";
    const int modbus_port = free_tcp_port();
    int http_port = free_tcp_port();
    while (http_port == modbus_port) http_port = free_tcp_port();
    fs::path config = write_config(s, run, modbus_port, true, http_port);
    for (const auto& [user, role] : {std::pair{"alice", "operator"}, std::pair{"bob", "viewer"}}) {
        const auto r = shell("echo " + std::string(user) + "-pass | " + TLSMON_BINARY +
                             " users add " + user + " --role " + role +
                             " --password-stdin --file " + quoted((run / "users.txt").string()));
        ASSERT_EQ(r.status, 0) << r.output;
    }
    {
        std::string text = read_text(config);
        const std::string http = "[http]\n";
        text.insert(text.find(http) + http.size(), "users_file = \"users.txt\"\n");
        // The demo's check zone on the abutment, scored against zero on the calibration page;
        // the 3-D vectors, drawn per area on the epoch view.
        text += abutment_check_zone(load_scene_file(s.dir / "scene.toml", std::nullopt));
        text += "\n[vectors]\nenabled = true\n";
        write_text(config, text);
    }
    const fs::path db = run / "tlsmon.sqlite", log = run / "daemon.log";
    DaemonProcess daemon(config, log);
    ASSERT_TRUE(wait_until([&] { return curl(http_port, "/api/v1/site").status == 200; }, 60))
        << read_text(log);
    for (int k = 0; k + 1 < kEpochs; ++k) {
        feed(s, k, run / "ingest");
        ASSERT_TRUE(wait_until([&] { return processed(db) == k + 1; }, 120))
            << "epoch " << k << "\n"
            << read_text(log);
    }

    const json last = sql(db,
                          "SELECT id FROM epochs WHERE status = 'done' ORDER BY acquired "
                          "DESC, id DESC LIMIT 1");
    ASSERT_EQ(last.size(), 1u);
    const std::int64_t last_id = last.at(0).at("id");
    const std::string base = "http://127.0.0.1:" + std::to_string(http_port);
    const json page = browser("pages " + quoted(base) + " " + quoted(artifacts().string()) + " " +
                              quoted(kStepZone) + " m3c2_median_m " + std::to_string(last_id));

    for (const auto& [name, errors] : page.at("errors").items())
        EXPECT_TRUE(errors.empty()) << name << " page console errors: " << errors.dump(1);

    // Overview: every zone quantity's newest row, as the database has it.
    const json latest = sql(db,
                            "SELECT z.name AS zone, q.name AS quantity, r.epoch_id AS epoch, "
                            "r.value AS value FROM zone_results r JOIN zones z ON z.id = "
                            "r.zone_id JOIN quantities q ON q.id = r.quantity_id JOIN epochs e "
                            "ON e.id = r.epoch_id WHERE e.acquired = (SELECT max(e2.acquired) "
                            "FROM zone_results r2 JOIN epochs e2 ON e2.id = r2.epoch_id WHERE "
                            "r2.zone_id = r.zone_id AND r2.quantity_id = r.quantity_id)");
    std::map<std::pair<std::string, std::string>, json> shown;
    for (const auto& v : page.at("overview").at("values"))
        shown[{v.at("zone"), v.at("quantity")}] = v;
    ASSERT_GT(latest.size(), 3u);
    EXPECT_EQ(shown.size(), latest.size());
    for (const auto& row : latest) {
        const auto it = shown.find({row.at("zone"), row.at("quantity")});
        ASSERT_NE(it, shown.end()) << "not on the overview: " << row.dump();
        EXPECT_EQ(it->second.at("epoch").get<std::int64_t>(), row.at("epoch").get<std::int64_t>());
        EXPECT_EQ(it->second.at("value").get<double>(), row.at("value").get<double>())
            << row.dump();
    }
    EXPECT_EQ(page.at("overview").at("last_epoch"), "#" + std::to_string(last_id));
    const json active = sql(db,
                            "SELECT r.name AS rule, s.state AS state FROM alarm_states s "
                            "JOIN alarm_rules r ON r.id = s.rule_id WHERE s.state != "
                            "'normal' ORDER BY r.name");
    std::set<std::string> rules_active, rules_shown;
    for (const auto& a : active)
        rules_active.insert(a.at("rule").get<std::string>() + " " +
                            a.at("state").get<std::string>());
    for (const auto& a : page.at("overview").at("alarms"))
        rules_shown.insert(a.at("rule").get<std::string>() + " " +
                           a.at("state").get<std::string>());
    EXPECT_EQ(rules_shown, rules_active);
    EXPECT_TRUE(rules_active.count(std::string(kStepRule) + " unack"))
        << "the step's rule is raised and shown";

    // Zone page: the chart's own rows are the database's points (time in ms, value in mm).
    const json points = sql(db,
                            "SELECT e.acquired AS t, r.value AS value FROM zone_results r "
                            "JOIN epochs e ON e.id = r.epoch_id WHERE r.zone_id = (SELECT id "
                            "FROM zones WHERE name = '" +
                                std::string(kStepZone) +
                                "') AND r.quantity_id = (SELECT id FROM quantities WHERE "
                                "name = 'm3c2_median_m') ORDER BY e.acquired");
    const json& rows = page.at("zone").at("rows");
    ASSERT_EQ(rows.size(), points.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(rows[i][0].get<double>(), 1000.0 * points[i].at("t").get<double>());
        EXPECT_NEAR(rows[i][1].get<double>(), 1000.0 * points[i].at("value").get<double>(), 1e-9);
    }
    // The CSV link downloads exactly what is shown.
    const std::string csv_path = page.at("zone").at("csv").get<std::string>().substr(base.size());
    const Answer csv = curl(http_port, csv_path);
    EXPECT_EQ(csv.status, 200);
    EXPECT_EQ(std::count(csv.body.begin(), csv.body.end(), '\n'),
              static_cast<long>(points.size()) + 1);

    // The zone page with the air temperature on the second axis: every epoch's, as stored.
    const json temperatures = sql(db,
                                  "SELECT e.acquired AS t, m.air_temperature_c AS c FROM "
                                  "meteo_sidecars m JOIN epochs e ON e.id = m.epoch_id WHERE "
                                  "m.outcome = 'used' ORDER BY e.acquired");
    const json& drawn = page.at("zone_meteo").at("values");
    ASSERT_GT(temperatures.size(), 3u);
    ASSERT_EQ(drawn.size(), temperatures.size()) << page.at("zone_meteo").dump();
    for (std::size_t i = 0; i < drawn.size(); ++i) {
        EXPECT_EQ(drawn[i][0].get<double>(), 1000.0 * temperatures[i].at("t").get<double>());
        EXPECT_DOUBLE_EQ(drawn[i][1].get<double>(), temperatures[i].at("c").get<double>());
    }
    EXPECT_EQ(page.at("zone_meteo").at("label"), "air temperature [°C]");

    // Epoch view: one mark per core point with a distance.
    const auto distance = core_point_array(db, last_id, "m3c2_distance_m");
    const auto defined =
        std::count_if(distance.begin(), distance.end(), [](float d) { return std::isfinite(d); });
    ASSERT_GT(defined, 100);
    EXPECT_EQ(page.at("epoch").at("distinct_core_points").get<long>(), defined);
    // One keypoint arrow per map zone with a keypoint vector in this epoch; its components
    // along the wall and up have the stored vector's length when the vector lies in the
    // wall (the zones are vertical faces: up is dz).
    const json vectors = sql(db,
                             "SELECT z.name AS zone, r.value AS dz FROM zone_results r JOIN "
                             "zones z ON z.id = r.zone_id JOIN quantities q ON q.id = "
                             "r.quantity_id WHERE q.name = 'keypoint_dz_m' AND r.epoch_id = " +
                                 std::to_string(last_id));
    std::set<std::string> with_vector;
    for (const auto& v : vectors) with_vector.insert(v.at("zone").get<std::string>());
    long arrows_expected = 0;
    for (const auto& [zone, arrows] : page.at("epoch").at("arrows").items()) {
        EXPECT_EQ(arrows.get<int>(), with_vector.count(zone) ? 1 : 0) << zone;
        arrows_expected += with_vector.count(zone) ? 1 : 0;
    }
    EXPECT_GT(arrows_expected, 0) << "the demo's zones carry keypoint vectors";
    for (const auto& v : vectors) {
        const auto it = page.at("epoch").at("vectors").find(v.at("zone").get<std::string>());
        // Not an M3C2 map zone, or one drawn in plan (v is then y).
        if (it == page.at("epoch").at("vectors").end() || (*it)[2] != "wall") continue;
        EXPECT_NEAR((*it)[1].get<double>(), v.at("dz").get<double>(), 1e-12) << v.dump();
    }

    // Calibration page over every epoch: the check zone's M3C2 median against zero, counted
    // here from the database (within σ = LoD95 / 1.96 and within LoD95), and every row as
    // `tlsmon calibration` prints it for the same database.
    const json& calibration = page.at("calibration");
    EXPECT_EQ(calibration.at("epochs"), sql(db, "SELECT count(*) AS n FROM epochs").at(0).at("n"));
    const json check = sql(db,
                           "SELECT z.name AS zone, r.value AS value, r.uncertainty AS lod FROM "
                           "zone_results r JOIN zones z ON z.id = r.zone_id JOIN quantities q ON "
                           "q.id = r.quantity_id WHERE json_extract(z.definition, '$.no_change') "
                           "AND q.name = 'm3c2_median_m' AND r.uncertainty IS NOT NULL AND "
                           "r.epoch_id != (SELECT epoch_id FROM reference_epoch)");
    ASSERT_GE(check.size(), 5u) << "the demo's check zone has an M3C2 median in every epoch";
    long within68 = 0, within95 = 0;
    for (const auto& r : check) {
        const double e = std::abs(r.at("value").get<double>());
        const double sigma = r.at("lod").get<double>() / 1.96;
        within68 += e <= sigma;
        within95 += e <= 1.96 * sigma;
    }
    std::map<std::pair<std::string, std::string>, json> shown_rows;
    for (const auto& r : calibration.at("rows")) shown_rows[{r.at("method"), r.at("part")}] = r;
    const auto it = shown_rows.find({"no_change:m3c2_median_m", check.at(0).at("zone")});
    ASSERT_NE(it, shown_rows.end()) << calibration.dump(1);
    EXPECT_EQ(it->second.at("n").get<std::size_t>(), check.size());
    EXPECT_EQ(it->second.at("within68").get<long>(), within68);
    EXPECT_EQ(it->second.at("within95").get<long>(), within95);
    const auto cli = shell("{ " + std::string(TLSMON_BINARY) + " calibration --format json --db " +
                           quoted(db.string()) + " 2>/dev/null; }");
    ASSERT_EQ(cli.status, 0) << cli.output;
    const json printed = json::parse(cli.output);
    EXPECT_EQ(printed.size(), shown_rows.size()) << cli.output;
    for (const auto& r : printed) {
        const auto row = shown_rows.find({r.at("method"), r.at("part")});
        ASSERT_NE(row, shown_rows.end()) << r.dump();
        const auto n = r.at("n").get<long>();
        EXPECT_EQ(row->second.at("n").get<long>(), n);
        EXPECT_EQ(row->second.at("within95").get<long>(),
                  std::lround(r.at("cover95_pct").get<double>() * n / 100))
            << r.dump();
        EXPECT_EQ(row->second.at("verdict95"), r.at("verdict95")) << r.dump();
    }

    // The 3-D vectors on the epoch view: one arrow per measured area (a σ stored) whose
    // centre lies in a map zone's box, its components along the wall those of the stored
    // vector (up is dz on a vertical face).
    const auto ax = core_point_array(db, last_id, "vector_x_m"),
               ay = core_point_array(db, last_id, "vector_y_m"),
               az = core_point_array(db, last_id, "vector_z_m"),
               adz = core_point_array(db, last_id, "vector_dz_m"),
               asx = core_point_array(db, last_id, "vector_sigma_x_m");
    ASSERT_GT(ax.size(), 10u) << "the vectors stage stored its areas";
    const json boxes = sql(db, "SELECT name, definition FROM zones");
    long drawn_areas = 0;
    for (const auto& [zone, count] : page.at("epoch").at("area_arrows").items()) {
        std::optional<json> box;
        for (const auto& b : boxes)
            if (b.at("name") == zone) box = json::parse(b.at("definition").get<std::string>());
        ASSERT_TRUE(box) << zone;
        long inside = 0;
        std::set<long> dz_um;  // the stored dz of the areas inside, in µm
        for (std::size_t k = 0; k < ax.size(); ++k) {
            const double p[3] = {ax[k], ay[k], az[k]};
            bool in = std::isfinite(asx[k]);
            for (int c = 0; c < 3; ++c)
                in = in && p[c] >= (*box)["min"][c].get<double>() &&
                     p[c] <= (*box)["max"][c].get<double>();
            inside += in;
            if (in) dz_um.insert(std::lround(1e6 * adz[k]));
        }
        EXPECT_EQ(count.get<long>(), inside) << zone;
        drawn_areas += inside;
        const auto up = page.at("epoch").at("area_dv").find(zone);
        if (up == page.at("epoch").at("area_dv").end() || (*up)[1] != "wall") continue;
        for (const auto& dv : (*up)[0])
            EXPECT_TRUE(dz_um.count(std::lround(1e6 * dv.get<double>())))
                << zone << ": an arrow's upward component is no stored area's dz: " << dv;
    }
    EXPECT_GT(drawn_areas, 10);

    // Alarms and events pages.
    const json states = sql(db, "SELECT count(*) AS n FROM alarm_states");
    EXPECT_EQ(page.at("alarms").size(), states.at(0).at("n").get<std::size_t>());
    const json events = sql(db,
                            "SELECT (SELECT count(*) FROM system_events) + (SELECT count(*) "
                            "FROM alarm_events) AS n");
    EXPECT_EQ(page.at("events").get<int>(), events.at(0).at("n").get<int>());

    // Hostile requests, each refused; the daemon answers and ingests throughout.
    for (const char* path :
         {"/static/../tlsmon.toml", "/static/%2e%2e/tlsmon.toml", "/static/..%2f..%2ftlsmon.toml",
          "/static/%2e%2e%2f%2e%2e%2fetc/passwd", "/static//etc/passwd", "/../../etc/passwd"}) {
        const Answer a = curl(http_port, path);
        EXPECT_TRUE(a.status == 404 || a.status == 400) << path << ": " << a.status;
        EXPECT_EQ(a.body.find("[paths]"), std::string::npos) << path;
        EXPECT_EQ(a.body.find("root:"), std::string::npos) << path;
    }
    EXPECT_EQ(curl(http_port, "/api/v1/site", "-X POST -d x=1").status, 405);
    EXPECT_EQ(curl(http_port, "/api/v1/site", "-X DELETE").status, 405);
    const Answer get_on_post = curl(http_port, "/api/v1/alarms/ack", "-i");
    EXPECT_EQ(get_on_post.status, 405) << "a GET on an action is the wrong method, not a lost page";
    EXPECT_NE(get_on_post.body.find("Allow: POST"), std::string::npos) << get_on_post.body;
    const Answer bad = curl(http_port, "/api/v1/series?zone=a&quantity=b&from=yesterday");
    EXPECT_EQ(bad.status, 400);
    EXPECT_NE(bad.body.find("'from'"), std::string::npos) << bad.body;
    EXPECT_EQ(curl(http_port, "/api/v1/series?zone=a").status, 400);
    // A date alone is a date, not a number of seconds: nothing after the year 2100.
    const Answer later = curl(http_port, "/api/v1/series?zone=" + std::string(kStepZone) +
                                             "&quantity=m3c2_median_m&from=2100-01-01");
    ASSERT_EQ(later.status, 200) << later.body;
    EXPECT_EQ(json::parse(later.body).at("total"), 0) << later.body;
    EXPECT_EQ(curl(http_port, "/api/v1/series?zone=a&quantity=b&width=-3").status, 400);
    EXPECT_EQ(curl(http_port, "/api/v1/epochs/999999").status, 404);
    const std::string big =
        "GET /api/v1/site HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(1 << 20, 'a') + "\r\n\r\n";
    const std::string refused = raw_request(http_port, big);
    EXPECT_TRUE(refused.empty() || refused.find(" 400 ") != std::string::npos)
        << "a 1 MB header is refused: " << refused;
    EXPECT_EQ(curl(http_port, "/api/v1/site").status, 200);

    // Operators: refusals first, each changing nothing; then alice acknowledges in the browser.
    const std::string rule_row =
        "SELECT s.state AS state, (SELECT count(*) FROM alarm_events e "
        "WHERE e.rule_id = r.id) AS events FROM alarm_rules r JOIN "
        "alarm_states s ON s.rule_id = r.id WHERE r.name = '" +
        std::string(kStepRule) + "'";
    const json before = sql(db, rule_row);
    ASSERT_EQ(before.at(0).at("state"), "unack");
    const fs::path jar = tmp.path() / "cookies";
    const std::string ack_body = std::string("{\"rule\":\"") + kStepRule + "\"}";
    const auto login = [&](const std::string& user, const std::string& password) {
        return curl(http_port, "/api/v1/login",
                    "-c " + quoted(jar.string()) +
                        " -X POST -H 'Content-Type: application/json' -d " +
                        quoted("{\"user\":\"" + user + "\",\"password\":\"" + password + "\"}"));
    };
    EXPECT_EQ(curl(http_port, "/api/v1/alarms/ack", "-X POST -d " + quoted(ack_body)).status, 401);
    const Answer viewer = login("bob", "bob-pass");
    ASSERT_EQ(viewer.status, 200) << viewer.body;
    const std::string viewer_csrf = json::parse(viewer.body).at("csrf");
    EXPECT_EQ(curl(http_port, "/api/v1/alarms/ack",
                   "-b " + quoted(jar.string()) + " -H 'X-CSRF-Token: " + viewer_csrf +
                       "' -X POST -d " + quoted(ack_body))
                  .status,
              403);
    ASSERT_EQ(login("alice", "alice-pass").status, 200);
    EXPECT_EQ(curl(http_port, "/api/v1/alarms/ack",
                   "-b " + quoted(jar.string()) + " -X POST -d " + quoted(ack_body))
                  .status,
              403)
        << "no X-CSRF-Token";
    EXPECT_EQ(curl(http_port, "/api/v1/alarms/ack",
                   "-b " + quoted(jar.string()) + " -H 'X-CSRF-Token: forged' -X POST -d " +
                       quoted(ack_body))
                  .status,
              403);
    EXPECT_EQ(sql(db, rule_row), before) << "a refused request changed the alarm";

    const json acted = browser("operator " + quoted(base) + " " + quoted(artifacts().string()) +
                               " alice alice-pass " + quoted(kStepRule) + " 'seen on site'");
    EXPECT_EQ(acted.at("state"), "ack");
    EXPECT_TRUE(acted.at("errors").empty()) << acted.at("errors").dump(1);
    const json ack = sql(db,
                         "SELECT e.actor AS actor, e.message AS message, s.state AS state, "
                         "r.id AS id FROM alarm_events e JOIN alarm_rules r ON r.id = "
                         "e.rule_id JOIN alarm_states s ON s.rule_id = r.id WHERE r.name = '" +
                             std::string(kStepRule) + "' AND e.kind = 'ack'");
    ASSERT_EQ(ack.size(), 1u);
    EXPECT_EQ(ack.at(0).at("state"), "ack");
    EXPECT_EQ(ack.at(0).at("actor"), "web user alice");
    EXPECT_NE(ack.at(0).at("message").get<std::string>().find("seen on site"), std::string::npos);
    EXPECT_EQ(sql(db,
                  "SELECT 1 FROM system_events WHERE kind = 'http_login' AND message LIKE "
                  "'user alice (operator) logged in from 127.0.0.1'")
                  .size(),
              2u)  // by curl, then in the browser
        << "each login is an event naming the user";
    // The step rule's block of discrete inputs (docs/modbus.md): its unacknowledged bit clears.
    const int bit = 16 + 4 * (ack.at(0).at("id").get<int>() - 1);
    EXPECT_TRUE(wait_until(
        [&] { return mbpoll_read(modbus_port, "1", bit + 3, 1) == std::vector<std::uint32_t>{0}; },
        15))
        << "the Modbus unacknowledged bit did not clear";

    // The API against its OpenAPI description (docs/openapi.yaml): every operation
    // exercised, every answer's status, content type and JSON body as described. Alice
    // takes the step's rule out of service and back, shelves and unshelves it.
    const auto openapi =
        shell("timeout 120 /usr/bin/python3 " +
              quoted(std::string(TLSMON_SOURCE_DIR) + "/tests/web/openapi_check.py") + " " +
              quoted(std::string(TLSMON_SOURCE_DIR) + "/docs/openapi.yaml") + " " + quoted(base) +
              " " + quoted(kStepZone) + " m3c2_median_m " + std::to_string(last_id) +
              " alice alice-pass " + quoted(kStepRule) + " 2>&1");
    EXPECT_EQ(openapi.status, 0) << openapi.output;
    if (openapi.status == 0) {
        const json verdict = json::parse(openapi.output);
        EXPECT_GE(verdict.at("checked").get<int>(), 25);
        EXPECT_EQ(verdict.at("operations").get<int>(), 22);  // every operation of docs/openapi.yaml
    }

    // Live: the overview, left open, shows the last epoch once it commits, with no reload;
    // meanwhile 100 wrong passwords from one address: 5 are checked, the rest refused.
    const fs::path ready = tmp.path() / "browser_ready";
    auto live = std::async(std::launch::async, [&] {
        return browser("live " + quoted(base) + " " + quoted(artifacts().string()) + " " +
                       quoted(ready.string()) + " 120");
    });
    ASSERT_TRUE(wait_until([&] { return fs::exists(ready); }, 60));
    feed(s, kEpochs - 1, run / "ingest");
    std::map<int, int> answers;
    for (int k = 0; k < 100; ++k) ++answers[login("alice", "wrong-" + std::to_string(k)).status];
    EXPECT_EQ(answers[401], 5);
    EXPECT_EQ(answers[429], 95);
    ASSERT_TRUE(wait_until([&] { return processed(db) == kEpochs; }, 120)) << read_text(log);
    const json seen = live.get();
    const json newest = sql(db,
                            "SELECT id FROM epochs WHERE status = 'done' ORDER BY acquired "
                            "DESC, id DESC LIMIT 1");
    EXPECT_EQ(seen.at("before"), "#" + std::to_string(last_id));
    EXPECT_EQ(seen.at("after"), "#" + std::to_string(newest.at(0).at("id").get<std::int64_t>()));
    EXPECT_EQ(seen.at("navigations"), 1) << "updated without a reload";
    EXPECT_TRUE(seen.at("errors").empty()) << seen.at("errors").dump(1);
    EXPECT_TRUE(daemon.running());
}

// Count of the entries of /proc/PID/<what> (fd: open descriptors, task: threads).
long proc_entries(pid_t pid, const char* what) {
    std::error_code ec;
    const fs::path dir = fs::path("/proc") / std::to_string(pid) / what;
    long n = 0;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) ++n;
    return n;
}

// 10,000 connections opened and left idle: the daemon holds at most http.threads served and
// as many waiting (daemon/http/connection_queue.hpp), its threads do not grow, an epoch
// commits meanwhile, and once the connections close the dashboard answers again.
TEST(Dashboard, TenThousandIdleConnectionsStayWithinTheConfiguredLimits) {
    constexpr int kThreads = 4, kConnections = 10000;
    TempDir tmp("dashboard-flood");
    const Scenario s = render_scenario(tmp.path() / "scenario", 2, next_midnight());
    const fs::path run = tmp.path() / "run";
    const int http_port = free_tcp_port();
    fs::path config = write_config(s, run, http_port + 1, false, http_port);  // Modbus off
    {
        std::string text = read_text(config);
        const std::string http = "[http]\n";
        text.insert(text.find(http) + http.size(),
                    "threads = " + std::to_string(kThreads) +
                        "\nmax_event_streams = 2\nidle_timeout = 2\n");
        write_text(config, text);
    }
    const fs::path db = run / "tlsmon.sqlite", log = run / "daemon.log";
    DaemonProcess daemon(config, log);
    ASSERT_TRUE(wait_until([&] { return curl(http_port, "/api/v1/site").status == 200; }, 60))
        << read_text(log);
    feed(s, 0, run / "ingest");
    ASSERT_TRUE(wait_until([&] { return processed(db) == 1; }, 120)) << read_text(log);
    const long fds_before = proc_entries(daemon.pid(), "fd");
    const long threads_before = proc_entries(daemon.pid(), "task");

    rlimit limit{};
    ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &limit), 0);
    const rlim_t wanted = kConnections + 1000;
    if (limit.rlim_cur < wanted) {
        limit.rlim_cur = wanted;
        limit.rlim_max = std::max(limit.rlim_max, wanted);
        ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &limit), 0) << "the test opens 10,000 sockets";
    }
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(http_port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    std::vector<int> idle;
    idle.reserve(kConnections);
    for (int i = 0; i < kConnections; ++i) {
        const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
        ASSERT_GE(fd, 0) << "socket " << i << ": " << std::strerror(errno);
        idle.push_back(fd);
        const int r = ::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to);
        ASSERT_TRUE(r == 0 || errno == EINPROGRESS)
            << "connect " << i << ": " << std::strerror(errno);
    }
    // An epoch during the flood; the daemon's descriptors and threads sampled meanwhile.
    feed(s, 1, run / "ingest");
    long fds_most = 0, threads_most = 0;
    const bool committed = wait_until(
        [&] {
            fds_most = std::max(fds_most, proc_entries(daemon.pid(), "fd"));
            threads_most = std::max(threads_most, proc_entries(daemon.pid(), "task"));
            return processed(db) == 2;
        },
        120);
    for (int fd : idle) ::close(fd);
    EXPECT_TRUE(committed) << read_text(log);
    EXPECT_EQ(sql(db, "SELECT count(*) AS n FROM epochs WHERE status = 'done'").at(0).at("n"), 2);
    // Served and waiting connections, one more in the accepting thread's hand, and a few the
    // epoch's own processing opens (its scan, the database's journal).
    EXPECT_LE(fds_most - fds_before, 2 * kThreads + 1 + 6)
        << "descriptors before " << fds_before << ", at most " << fds_most;
    EXPECT_LE(threads_most - threads_before, 4)
        << "threads before " << threads_before << ", at most " << threads_most;
    EXPECT_TRUE(wait_until([&] { return curl(http_port, "/api/v1/site").status == 200; }, 60))
        << "the dashboard answers again once the connections are gone";
    EXPECT_TRUE(daemon.running());
}

// HTTPS with the configured certificate (http.certificate, http.private_key): a client that
// trusts that certificate reads the API and logs in (the session cookie `Secure`); plain HTTP
// on that port gets no answer; a key that is not the certificate's stops the start, named;
// one without the other is a configuration error.
TEST(Dashboard, ServesHttpsWithTheConfiguredCertificateOnly) {
    TempDir tmp("dashboard-tls");
    const Scenario s = render_scenario(tmp.path() / "scenario", 1, next_midnight());
    const fs::path run = tmp.path() / "run";
    const int http_port = free_tcp_port();
    const fs::path config = write_config(s, run, http_port + 1, false, http_port);
    const auto openssl = [&](const std::string& args) {
        const auto r = shell("cd " + quoted(run.string()) + " && openssl " + args + " 2>&1");
        ASSERT_EQ(r.status, 0) << r.output;
    };
    openssl(
        "req -x509 -newkey rsa:2048 -nodes -keyout key.pem -out cert.pem -days 2 "
        "-subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1");
    openssl("genrsa -out other-key.pem 2048");
    ASSERT_EQ(shell("echo alice-pass | " + std::string(TLSMON_BINARY) +
                    " users add alice --role operator --password-stdin --file " +
                    quoted((run / "users.txt").string()))
                  .status,
              0);
    const std::string text = read_text(config);
    const auto with_http = [&](const std::string& keys) {
        std::string t = text;
        t.insert(t.find("[http]\n") + 7, keys);
        return t;
    };
    write_text(config, with_http("certificate = \"cert.pem\"\nprivate_key = \"key.pem\"\n"
                                 "users_file = \"users.txt\"\n"));
    const fs::path log = run / "daemon.log";
    {
        DaemonProcess daemon(config, log);
        const std::string https = "https://127.0.0.1:" + std::to_string(http_port);
        const std::string trust = "--cacert " + quoted((run / "cert.pem").string());
        const auto get = [&](const std::string& options, const std::string& url) {
            return shell("curl -s -m 10 -o /dev/null -w '%{http_code}' " + options + " " +
                         quoted(url))
                .output;
        };
        ASSERT_TRUE(wait_until([&] { return get(trust, https + "/api/v1/site") == "200"; }, 60))
            << read_text(log);
        EXPECT_NE(get("", https + "/api/v1/site"), "200") << "an unknown certificate is trusted";
        EXPECT_NE(get("", "http://127.0.0.1:" + std::to_string(http_port) + "/api/v1/site"), "200")
            << "plain HTTP answered on the HTTPS port";
        const auto login = shell("curl -s -i -m 10 " + trust +
                                 " -X POST -H 'Content-Type: application/json' -d "
                                 "'{\"user\":\"alice\",\"password\":\"alice-pass\"}' " +
                                 quoted(https + "/api/v1/login"));
        EXPECT_NE(login.output.find("HTTP/1.1 200"), std::string::npos) << login.output;
        EXPECT_NE(login.output.find("HttpOnly; SameSite=Strict; Secure; Max-Age="),
                  std::string::npos)
            << login.output;
        EXPECT_NE(read_text(log).find("dashboard on https://127.0.0.1:"), std::string::npos);
        EXPECT_TRUE(daemon.running());
    }
    // A key that is not the certificate's: the daemon does not start, and says why.
    write_text(config, with_http("certificate = \"cert.pem\"\nprivate_key = \"other-key.pem\"\n"));
    const auto refused = shell("timeout 60 " + std::string(TLSMON_BINARY) + " run --config " +
                               quoted(config.string()) + " 2>&1");
    EXPECT_NE(refused.status, 0);
    EXPECT_NE(refused.status, 124) << "it kept running";
    EXPECT_NE(refused.output.find("cannot use the certificate " + (run / "cert.pem").string()),
              std::string::npos)
        << refused.output;
    // One without the other is refused by the configuration check.
    write_text(config, with_http("certificate = \"cert.pem\"\n"));
    const auto half =
        shell(std::string(TLSMON_BINARY) + " check-config " + quoted(config.string()) + " 2>&1");
    EXPECT_NE(half.status, 0);
    EXPECT_NE(half.output.find("HTTPS needs both http.certificate and http.private_key"),
              std::string::npos)
        << half.output;
}

}  // namespace
}  // namespace tlsmon::test::e2e
