// The real daemon's Modbus server read and written with the real `mbpoll` (Debian package):
// heartbeat, test float in both word orders, zone values written into the database, an
// acknowledge coil that leaves an acknowledgement by SCADA in the database, and the
// `tlsmon modbus-map` rows against the server's answers.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>

#include "tests/support/daemon_harness.hpp"
#include "tests/support/modbus_client.hpp"

namespace tlsmon {
namespace {

using test::DaemonProcess;
using test::read_file;
using test::shell;
using test::wait_until;
namespace fs = std::filesystem;

std::string modbus_toml(int port, const std::string& word_order) {
    return "[modbus]\nenabled = true\nport = " + std::to_string(port) + "\nword_order = \"" +
           word_order +
           "\"\nsnapshot_interval = 0.2\nquantities = [\"m3c2_median_m\", \"keypoint_dz_m\"]\n"
           "[[zone]]\nname = \"pier top\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
           "[[zone]]\nname = \"pier foot\"\nmin = [0, 0, -1]\nmax = [1, 1, 0]\n";
}

// `mbpoll` once, 0-based addresses, writing `write` when given; the values it prints, in
// order ("[addr]: value").
struct Poll {
    int status = -1;
    std::vector<double> values;
    std::string output;
};

Poll mbpoll(int port, const std::string& args, const std::string& write = "") {
    Poll p;
    const auto r = shell("timeout 10 mbpoll -m tcp -a 1 -p " + std::to_string(port) +
                         " -0 -1 -o 2 " + args + " 127.0.0.1 " + write);
    p.status = r.status;
    p.output = r.output;
    const std::regex row(R"(\[\d+\]:\s+(\S+))");
    for (std::sregex_iterator it(r.output.begin(), r.output.end(), row), end; it != end; ++it) {
        const std::string v = (*it)[1];
        p.values.push_back(v == "nan" || v == "-nan" ? std::nan("") : std::stod(v));
    }
    return p;
}

// One done epoch acquired at `acquired` with the given zone results, through the storage API.
// The running daemon may claim a fresh pending epoch first (its file does not exist): then
// another one is made.
void write_epoch(const test::Site& site, UtcSeconds acquired, std::vector<ZoneResult> results,
                 int serial) {
    auto db = EpochDatabase::open(site.database(), EpochDatabase::Mode::read_write);
    for (int attempt = 0; attempt < 10; ++attempt) {
        char sha[65];
        std::snprintf(sha, sizeof sha, "%064x", serial * 100 + attempt);
        const auto id =
            db.epochs().insert({sha, acquired, site.root / "gone.ptx", 1, std::nullopt}).id;
        if (!db.epochs().claim(id)) continue;
        EpochResults r;
        r.zone_results = results;
        db.results().commit(id, r);
        return;
    }
    FAIL() << "could not claim an epoch";
}

struct Running {
    explicit Running(const std::string& name, const std::string& word_order = "ABCD")
        : port(test::free_tcp_port()), site(name, modbus_toml(port, word_order)) {
        // The database with its zones before the daemon starts, so the test's ids are known.
        fs::create_directories(site.database().parent_path());
        auto db = EpochDatabase::open(site.database(), EpochDatabase::Mode::read_write);
        db.site().upsert_zone("pier top", "{}");
        db.site().upsert_zone("pier foot", "{}");
    }
    void start() {
        daemon.emplace(site.config(), site.log());
        ASSERT_TRUE(wait_until([&] { return mbpoll(port, "-t 3 -r 0 -c 1").status == 0; }, 20))
            << shell("cat " + site.log().string()).output;
    }
    int port;
    test::Site site;
    std::optional<DaemonProcess> daemon;
};

TEST(ModbusProcess, HeartbeatCountsSecondsAndTestFloatReads123456) {
    Running r("modbus_heartbeat");
    r.start();
    const Poll first = mbpoll(r.port, "-t 3 -r 1 -c 1");
    ASSERT_EQ(first.values.size(), 1u) << first.output;
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    const Poll second = mbpoll(r.port, "-t 3 -r 1 -c 1");
    ASSERT_EQ(second.values.size(), 1u) << second.output;
    EXPECT_GE(second.values[0] - first.values[0], 2);  // +1 per second, 2.5 s later
    EXPECT_LE(second.values[0] - first.values[0], 3);
    // mbpoll -B: big-endian word order (ABCD); the map's version at address 0.
    const Poll f = mbpoll(r.port, "-t 3:float -B -r 7 -c 1");
    ASSERT_EQ(f.values.size(), 1u) << f.output;
    EXPECT_EQ(f.values[0], 123456.0);
    const Poll words = mbpoll(r.port, "-t 3:hex -r 7 -c 2");
    EXPECT_NE(words.output.find("0x47F1"), std::string::npos) << words.output;
    EXPECT_NE(words.output.find("0x2000"), std::string::npos) << words.output;
    EXPECT_EQ(mbpoll(r.port, "-t 3 -r 0 -c 1").values, std::vector<double>{1});
}

// A port changed by SIGHUP was logged as reloaded and not applied: SCADA polled a port
// that the file no longer named. The server now moves to the new port at the reload.
TEST(ModbusProcess, PortChangedBySighupIsServedAtOnce) {
    Running r("modbus_reload");
    r.start();
    const int moved = test::free_tcp_port();
    std::string text = read_file(r.site.config());
    const std::string old_port = "port = " + std::to_string(r.port);
    text.replace(text.find(old_port), old_port.size(), "port = " + std::to_string(moved));
    std::ofstream(r.site.config()) << text;
    r.daemon->signal(SIGHUP);
    ASSERT_TRUE(wait_until([&] { return mbpoll(moved, "-t 3 -r 0 -c 1").status == 0; }, 10))
        << read_file(r.site.log());
    EXPECT_EQ(mbpoll(moved, "-t 3:float -B -r 7 -c 1").values, std::vector<double>{123456.0});
    EXPECT_NE(mbpoll(r.port, "-t 3 -r 0 -c 1").status, 0) << "the old port is closed";
    bool said = false;
    for (const auto& e : r.site.open_db().series().events({}, std::string("config_reload"))) {
        said = said || e.message.find("Modbus server restarted on 127.0.0.1:" +
                                      std::to_string(moved)) != std::string::npos;
    }
    EXPECT_TRUE(said);
}

TEST(ModbusProcess, CdabWordOrderReadsWithMbpollsDefault) {
    Running r("modbus_cdab", "CDAB");
    r.start();
    const Poll f = mbpoll(r.port, "-t 3:float -r 7 -c 1");  // mbpoll's default: low word first
    ASSERT_EQ(f.values.size(), 1u) << f.output;
    EXPECT_EQ(f.values[0], 123456.0);
}

TEST(ModbusProcess, ZoneValuesFromTheDatabaseAppearInTheMappedRegisters) {
    Running r("modbus_values");
    r.start();
    const UtcSeconds now = now_utc();
    // pier foot (zone id 2, slot 1), keypoint_dz_m (slot 1): block 100 + 80 + 10 = 190.
    // Two epochs 12 h apart: the rate is (-0.003 - 0.001) / 0.5 d = -0.008 m/d.
    write_epoch(r.site, now - 43260, {{"pier foot", "keypoint_dz_m", 0.001, 0.002, 40, false}}, 1);
    write_epoch(r.site, now - 60, {{"pier foot", "keypoint_dz_m", -0.003, 0.002, 40, true}}, 2);
    Poll p;
    ASSERT_TRUE(wait_until(
        [&] {
            p = mbpoll(r.port, "-t 3:float -B -r 190 -c 3");
            return p.values.size() == 3 && std::abs(p.values[0] + 0.003) < 1e-9;
        },
        10))
        << p.output;
    EXPECT_NEAR(p.values[1], 0.002, 1e-9);   // LoD
    EXPECT_NEAR(p.values[2], -0.008, 1e-7);  // rate, m/d
    const Poll q = mbpoll(r.port, "-t 3 -r 196 -c 1");
    EXPECT_EQ(q.values, std::vector<double>{1});  // valid, fresh, significant
    // The other quantity of the zone has no value: NaN, quality 0.
    const Poll none = mbpoll(r.port, "-t 3:float -B -r 180 -c 1");
    ASSERT_EQ(none.values.size(), 1u) << none.output;
    EXPECT_TRUE(std::isnan(none.values[0])) << none.output;
    EXPECT_EQ(mbpoll(r.port, "-t 3 -r 186 -c 1").values, std::vector<double>{0});
    // Epochs processed (uint32 at 5) = 2; out of the map: an exception, no value.
    const Poll count = mbpoll(r.port, "-t 3:int -B -r 5 -c 1");
    EXPECT_EQ(count.values, std::vector<double>{2}) << count.output;
    EXPECT_NE(mbpoll(r.port, "-t 3 -r 5000 -c 1").status, 0);
    // Holding registers do not exist and nothing there is writable.
    EXPECT_NE(mbpoll(r.port, "-t 4 -r 0", "1").status, 0);
}

TEST(ModbusProcess, AcknowledgeCoilLeavesAnAcknowledgementBySCADA) {
    Running r("modbus_ack");
    {
        auto db = EpochDatabase::open(r.site.database(), EpochDatabase::Mode::read_write);
        db.alarms().upsert_rule({0, "top settles", "pier top", "m3c2_median_m", "{}", true});
        db.alarms().upsert_rule({0, "foot tilts", "pier foot", "keypoint_dz_m", "{}", true});
        db.alarms().set_state({"top settles", "unack", "alarm", now_utc() - 100, 0.02, std::nullopt,
                               "alarm", std::nullopt, "", std::nullopt});
        db.alarms().set_state({"foot tilts", "unack", "warning", now_utc() - 100, 0.01,
                               std::nullopt, "warning", std::nullopt, "", std::nullopt});
    }
    r.start();
    // Rule "foot tilts" has id 2, slot 1: bits 20..23, coil 17.
    Poll bits;
    ASSERT_TRUE(wait_until(
        [&] {
            bits = mbpoll(r.port, "-t 1 -r 16 -c 8");
            return bits.values.size() == 8 && bits.values[7] == 1;
        },
        10))
        << bits.output;
    EXPECT_EQ(bits.values, (std::vector<double>{1, 1, 1, 1, 1, 0, 0, 1}));
    const Poll write = mbpoll(r.port, "-t 0 -r 17", "1");
    ASSERT_EQ(write.status, 0) << write.output;
    // The state and its event row (two writes): wait for both.
    const auto acknowledged = [&] {
        const auto db = r.site.open_db();
        bool state_ack = false, event_by_scada = false;
        for (const auto& s : db.alarms().states()) {
            if (s.rule == "foot tilts") state_ack = s.state == "ack";
        }
        for (const auto& e : db.series().events({})) {
            if (e.rule == "foot tilts" && e.kind == "ack") {
                // Who: the SCADA client's address and port, not only "SCADA".
                event_by_scada =
                    e.message.find("by SCADA (modbus client 127.0.0.1:") != std::string::npos;
            }
        }
        return state_ack && event_by_scada;
    };
    ASSERT_TRUE(wait_until(acknowledged, 10));
    for (const auto& s : r.site.open_db().alarms().states()) {
        if (s.rule == "top settles") {
            EXPECT_EQ(s.state, "unack") << "only the written coil's rule is acknowledged";
        }
    }
    // Self-resetting: the coil reads 0; the rule's unacknowledged bit clears.
    EXPECT_EQ(mbpoll(r.port, "-t 0 -r 17 -c 1").values, std::vector<double>{0});
    ASSERT_TRUE(wait_until(
        [&] { return mbpoll(r.port, "-t 1 -r 23 -c 1").values == std::vector<double>{0}; }, 10));
    // A reserved coil and a discrete input are not writable.
    EXPECT_NE(mbpoll(r.port, "-t 0 -r 5", "1").status, 0);
}

TEST(ModbusProcess, MapPrintedForTheIntegratorIsWhatTheServerAnswers) {
    Running r("modbus_map");
    r.start();
    const auto map = shell(std::string(TLSMON_BINARY) + " modbus-map --format csv --config " +
                           r.site.config().string());
    ASSERT_EQ(map.status, 0) << map.output;
    // Every input register row: readable at its address with its count; the known ones
    // hold their truth.
    const std::regex row(R"(^input register,(\d+),(\d+),([^,]*),(\w+),)");
    int rows = 0;
    std::istringstream lines(map.output);
    for (std::string line; std::getline(lines, line);) {
        std::smatch m;
        if (!std::regex_search(line, m, row)) continue;
        ++rows;
        const std::string address = m[1], name = m[3], type = m[4];
        const std::string t = type == "float32"                     ? "3:float -B"
                              : type == "uint32" || type == "int32" ? "3:int -B"
                                                                    : "3";
        const Poll p = mbpoll(r.port, "-t " + t + " -r " + address + " -c 1");
        ASSERT_EQ(p.status, 0) << line << "\n" << p.output;
        ASSERT_EQ(p.values.size(), 1u) << line << "\n" << p.output;
        if (name == "test_float") {
            EXPECT_EQ(p.values[0], 123456.0);
        }
        if (name == "map_version") {
            EXPECT_EQ(p.values[0], 1);
        }
        if (name.find(".value") != std::string::npos) {
            EXPECT_TRUE(std::isnan(p.values[0])) << name;
        }
    }
    EXPECT_EQ(rows, 6 + 2 * 2 * 6);  // fixed + zones x quantities x rows
    EXPECT_NE(map.output.find("coil,0,1,acknowledge_all,"), std::string::npos);
}

TEST(ModbusProcess, AllowlistMaxClientsAndUnitIdAreEnforced) {
    const int port = test::free_tcp_port();
    test::Site site("modbus_limits", "[modbus]\nenabled = true\nport = " + std::to_string(port) +
                                         "\nmax_clients = 2\nunit_id = 3\n");
    DaemonProcess daemon(site.config(), site.log());
    test::ModbusTcpClient a, b, c;
    ASSERT_TRUE(wait_until([&] { return a.connect(port) && !a.closed_by_peer(300); }, 20));
    ASSERT_TRUE(b.connect(port));
    ASSERT_TRUE(c.connect(port));
    EXPECT_TRUE(c.closed_by_peer(2000)) << "a third client beyond max_clients = 2";
    // Unit 3 is answered; a request for unit 1 is not (no answer within 500 ms).
    b.unit = 3;
    const auto version = b.read_input_registers(0, 1, 2000);
    ASSERT_TRUE(version.has_value());
    EXPECT_EQ((*version)[0], 1);
    EXPECT_FALSE(a.read_input_registers(0, 1, 500).has_value());
    daemon.signal(SIGTERM);
    ASSERT_EQ(daemon.wait(20), 0);

    const int port2 = test::free_tcp_port();
    test::Site listed("modbus_allowlist",
                      "[modbus]\nenabled = true\nport = " + std::to_string(port2) +
                          "\nallowlist = [\"10.9.9.9\"]\n");
    DaemonProcess second(listed.config(), listed.log());
    ASSERT_TRUE(wait_until(
        [&] { return shell("grep -q 'modbus: listening' " + listed.log().string()).status == 0; },
        20));
    test::ModbusTcpClient d;
    ASSERT_TRUE(d.connect(port2));
    EXPECT_TRUE(d.closed_by_peer(2000)) << "127.0.0.1 is not in the allowlist";
}

}  // namespace
}  // namespace tlsmon
