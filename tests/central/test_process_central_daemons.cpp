// Three site daemons forwarding into one real PostgreSQL 15 (docs/central.md), on the demo's
// scenario (registration on targets, M3C2 zones, the knocked target, the step raising its
// rule):
//   - the central database stopped while 20 epochs arrive: every site goes on ingesting and
//     alarming, raises system.central_forward, and once the server is back its backlog
//     arrives, in order, once;
//   - the site daemons killed with SIGKILL at random moments, one of them per epoch while the
//     server is down (each in turn), and site "b" again while its backlog drains in small
//     batches (so kills fall between the central commit and marking the entries sent);
//   - the central database read-only: the sites go on, raise the system alarm, catch up;
//   - at the end each site's SQLite file (read by sqlite3) equals its rows in the central
//     database (read by psql): epochs, registrations, zone results to the bit, alarm and
//     system events; site "c" (forward_arrays) its core point arrays byte for byte, the
//     others none.
#include <gtest/gtest.h>

#include <iostream>
#include <map>
#include <random>
#include <sstream>

#include "central/central_schema.hpp"
#include "central/central_sites.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/postgres_cluster.hpp"

namespace tlsmon::test::e2e {
namespace {

constexpr int kEpochs = 24;
constexpr int kBefore = 2;   // epochs forwarded before the outage
constexpr int kOutage = 20;  // epochs that arrive while the central database is stopped

std::map<std::string, std::string> psql_keyed(const PostgresCluster& pg, const std::string& query) {
    std::map<std::string, std::string> out;
    std::istringstream in(pg.psql(query));
    for (std::string l; std::getline(in, l);) {
        const auto bar = l.find('|');
        out[l.substr(0, bar)] += l.substr(bar + 1) + "\n";
    }
    return out;
}

std::map<std::string, std::string> sqlite_keyed(const fs::path& db, const std::string& query) {
    std::map<std::string, std::string> out;
    for (const auto& row : sql(db, query)) {
        const std::string l = row.at("l");
        const auto bar = l.find('|');
        out[l.substr(0, bar)] += l.substr(bar + 1) + "\n";
    }
    return out;
}

// Rows "key|real" of psql, and rows {k, v} of sqlite3 (v printed with 17 digits), as
// key -> the double: both texts read back to the stored value, whatever their length.
std::map<std::string, double> psql_numbers(const PostgresCluster& pg, const std::string& query,
                                           std::size_t& rows) {
    std::map<std::string, double> out;
    std::istringstream in(pg.psql(query));
    rows = 0;
    for (std::string l; std::getline(in, l); ++rows) {
        const auto bar = l.rfind('|');
        out[l.substr(0, bar)] = std::stod(l.substr(bar + 1));
    }
    return out;
}

std::map<std::string, double> sqlite_numbers(const fs::path& db, const std::string& query) {
    std::map<std::string, double> out;
    for (const auto& row : sql(db, query))
        out[row.at("k")] = std::stod(row.at("v").get<std::string>());
    return out;
}

struct SiteRun {
    std::string name;
    fs::path run, config, db, log;
    std::unique_ptr<DaemonProcess> daemon;
    void start() { daemon = std::make_unique<DaemonProcess>(config, log); }
    void kill() {
        daemon->signal(SIGKILL);
        EXPECT_EQ(daemon->wait(10), -2);
        daemon.reset();
    }
    int pending() const { return sql(db, "SELECT count(*) AS n FROM outbox").at(0).at("n"); }
    std::string forward_alarm() const {
        const json r = sql(db,
                           "SELECT s.state AS state FROM alarm_states s JOIN alarm_rules r ON"
                           " r.id = s.rule_id WHERE r.name = 'system.central_forward'");
        return r.empty() ? "" : r.at(0).at("state").get<std::string>();
    }
    std::int64_t sent_upto() const {
        return sql(db, "SELECT sent_upto AS n FROM central_forward").at(0).at("n");
    }
    std::string source() const {
        return sql(db, "SELECT database_id AS s FROM central_forward").at(0).at("s");
    }
};

// The central database's rows of `site` against its SQLite file, table by table. Reals are
// compared as the doubles they are (psql's shortest text and sqlite3's 17 digits both read
// back exactly); times as UTC seconds. The events the daemon wrote as it stopped, after its
// forwarder had stopped, wait in the outbox for its next start: they are left out.
void expect_same(const PostgresCluster& pg, const SiteRun& s) {
    const std::string site = "(SELECT id FROM tlsmon.sites WHERE name = '" + s.name + "')";
    SCOPED_TRACE("site " + s.name);
    EXPECT_EQ(psql_keyed(pg,
                         "SELECT sha256, extract(epoch FROM acquired)::bigint || ' ' ||"
                         " status FROM tlsmon.epochs WHERE site_id = " +
                             site),
              sqlite_keyed(s.db,
                           "SELECT sha256 || '|' || acquired || ' ' || status AS l FROM"
                           " epochs WHERE status IN ('done', 'rejected', 'failed')"));
    std::size_t rows = 0;
    EXPECT_EQ(psql_numbers(pg,
                           "SELECT sha256 || ' ' || method || ' ' || accepted::int || '|' ||"
                           " rms_m FROM tlsmon.registrations WHERE site_id = " +
                               site,
                           rows),
              sqlite_numbers(s.db,
                             "SELECT e.sha256 || ' ' || r.method || ' ' || r.accepted AS k,"
                             " printf('%!.17g', r.rms_m) AS v FROM registrations r JOIN"
                             " epochs e ON e.id = r.epoch_id"));
    // Zone results: keyed by zone, quantity, time and epoch; the value to the bit.
    const auto central = psql_numbers(
        pg,
        "SELECT zone || ' ' || quantity || ' ' || extract(epoch FROM acquired)::bigint ||"
        " ' ' || sha256 || '|' || value FROM tlsmon.zone_results WHERE site_id = " +
            site,
        rows);
    const auto local = sqlite_numbers(
        s.db,
        "SELECT z.name || ' ' || q.name || ' ' || r.acquired || ' ' || e.sha256 AS k,"
        " printf('%!.17g', r.value) AS v FROM zone_results r JOIN zones z ON z.id ="
        " r.zone_id JOIN quantities q ON q.id = r.quantity_id JOIN epochs e ON e.id ="
        " r.epoch_id");
    EXPECT_EQ(rows, central.size()) << "a zone result twice";
    EXPECT_GT(local.size(), 100u);
    EXPECT_EQ(central, local);
    EXPECT_EQ(psql_keyed(pg,
                         "SELECT site_event_id, rule || ' ' || kind || ' ' || level || ' ' ||"
                         " actor || ' ' || extract(epoch FROM time)::bigint FROM"
                         " tlsmon.alarm_events WHERE site_id = " +
                             site),
              sqlite_keyed(s.db,
                           "SELECT a.id || '|' || r.name || ' ' || a.kind || ' ' ||"
                           " a.level || ' ' || a.actor || ' ' || a.time AS l FROM"
                           " alarm_events a JOIN alarm_rules r ON r.id = a.rule_id"));
    // Core point arrays: only c forwards them, every one byte for byte.
    const auto arrays = psql_keyed(pg,
                                   "SELECT sha256 || ' ' || quantity, encode(data, 'hex') FROM"
                                   " tlsmon.core_point_arrays WHERE site_id = " +
                                       site);
    if (s.name == "c") {
        EXPECT_GT(arrays.size(), 20u);
        EXPECT_TRUE(arrays == sqlite_keyed(s.db,
                                           "SELECT e.sha256 || ' ' || a.quantity || '|' ||"
                                           " lower(hex(a.data)) AS l FROM core_point_arrays a"
                                           " JOIN epochs e ON e.id = a.epoch_id"));
    } else {
        EXPECT_TRUE(arrays.empty());
    }
    // Messages on one line in both (one may hold a newline).
    EXPECT_EQ(psql_keyed(pg,
                         "SELECT site_event_id, kind || ' ' || level || ' ' ||"
                         " replace(message, E'\\n', ' ') FROM tlsmon.system_events WHERE"
                         " site_id = " +
                             site),
              sqlite_keyed(s.db,
                           "SELECT id || '|' || kind || ' ' || level || ' ' ||"
                           " replace(message, char(10), ' ') AS l FROM system_events WHERE"
                           " id NOT IN (SELECT json_extract(payload, '$.id') FROM outbox"
                           " WHERE kind = 'system_event')"));
}

TEST(CentralDaemons, ThreeSitesThroughAnOutageKillsAndAReadOnlyServerArriveWholeAndOnce) {
    TempDir tmp("central-e2e");
    const Scenario s = shared_scenario(kEpochs, next_midnight());
    PostgresCluster pg;
    {
        CentralTarget admin;
        admin.url = pg.url("postgres");
        admin.password_file = pg.admin_password_file();
        PgConnection c = PgConnection::open(admin);
        migrate_central(c);
        for (const char* name : {"a", "b", "c"}) {
            write_text(tmp.path() / (std::string(name) + ".pw"), std::string("secret-") + name);
            add_site(c, name, "", std::string("secret-") + name);
        }
    }
    std::vector<SiteRun> sites;
    for (const char* name : {"a", "b", "c"}) {
        SiteRun r;
        r.name = name;
        r.run = tmp.path() / name;
        r.config = write_config(s, r.run, free_tcp_port(), false);
        // b forwards in small batches, so its backlog takes many calls to drain.
        const int batch = r.name == "b" ? 3 : 200;
        write_text(r.config, read_text(r.config) + "\n[central]\nenabled = true\nurl = \"" +
                                 pg.url(site_role(name)) + "\"\npassword_file = \"" +
                                 (tmp.path() / (r.name + ".pw")).string() +
                                 "\"\nbatch_size = " + std::to_string(batch) +
                                 "\npoll = \"200ms\"\nretry_initial = \"200ms\"\nretry_max = 1\n"
                                 "alarm_after = 0\n");
        // c forwards its core point arrays too.
        if (r.name == "c") write_text(r.config, read_text(r.config) + "forward_arrays = true\n");
        r.db = r.run / "tlsmon.sqlite";
        r.log = r.run / "daemon.log";
        sites.push_back(std::move(r));
    }
    auto feed_all = [&](int k) {
        for (auto& r : sites) feed(s, k, r.run / "ingest");
    };
    // Every site has processed n epochs (a failure says which did not, and its log).
    auto all_processed = [&](int n) -> ::testing::AssertionResult {
        for (auto& r : sites) {
            if (!wait_until([&] { return processed(r.db) == n; }, 180))
                return ::testing::AssertionFailure()
                       << r.name << ": " << processed(r.db) << " of " << n << " epochs\n"
                       << read_text(r.log);
        }
        return ::testing::AssertionSuccess();
    };
    for (auto& r : sites) r.start();

    // Forwarded as they come.
    for (int k = 0; k < kBefore; ++k) feed_all(k);
    ASSERT_TRUE(all_processed(kBefore));
    for (auto& r : sites) {
        ASSERT_TRUE(wait_until([&] { return r.pending() == 0; }, 30)) << read_text(r.log);
    }
    EXPECT_EQ(pg.psql("SELECT count(*) FROM tlsmon.epochs"), std::to_string(3 * kBefore) + "\n");

    // The central database stopped for 20 epochs; one site killed per epoch, each in turn.
    pg.stop();
    std::mt19937 random(20261203);
    std::uniform_int_distribution<int> pause_ms(100, 1500);
    int kills = 0;
    for (int k = kBefore; k < kBefore + kOutage; ++k) {
        feed_all(k);
        std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(random)));
        SiteRun& victim = sites[static_cast<std::size_t>(k % 3)];
        victim.kill();
        ++kills;
        victim.start();
    }
    ASSERT_TRUE(all_processed(kBefore + kOutage));
    for (auto& r : sites) {
        SCOPED_TRACE(r.name);
        ASSERT_TRUE(wait_until([&] { return r.forward_alarm() == "unack"; }, 30))
            << read_text(r.log);
        EXPECT_GT(r.pending(), 0);
        // Alarming went on locally: the step (at N/2, inside the outage) raised its rule.
        EXPECT_EQ(sql(r.db,
                      "SELECT count(*) AS n FROM alarm_events a JOIN alarm_rules r ON"
                      " r.id = a.rule_id WHERE r.name = '" +
                          std::string(kStepRule) + "' AND a.kind = 'raise'")
                      .at(0)
                      .at("n"),
                  1);
    }
    const auto status = shell(std::string(TLSMON_BINARY) + " central status --db " +
                              sites[0].db.string() + " --format json");
    ASSERT_EQ(status.status, 0) << status.output;
    const json st = json::parse(status.output);
    EXPECT_GT(st.at("pending_entries").get<int>(), 0);
    EXPECT_NE(st.at("last_error").get<std::string>().find("127.0.0.1"), std::string::npos)
        << st.dump();

    // Back: the backlogs drain; b is killed while its small batches go out.
    pg.start();
    int in_the_window = 0;
    const std::string b_cursor =
        "SELECT coalesce(max(forwarded_seq), 0) FROM tlsmon.site_cursors WHERE source = '" +
        sites[1].source() + "'";
    for (int k = 0; k < 6 && sites[1].pending() > 0; ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(random)));
        sites[1].kill();
        ++kills;
        // The central database committed more than the site marked sent: the kill fell
        // between the two.
        in_the_window += std::stoll(pg.psql(b_cursor)) > sites[1].sent_upto();
        sites[1].start();
    }
    // The alarm's clear is written after a successful call and sent by the next: waited
    // for first, then the empty outbox.
    for (auto& r : sites) {
        SCOPED_TRACE(r.name);
        ASSERT_TRUE(wait_until([&] { return r.forward_alarm() == "rtn_unack"; }, 120))
            << read_text(r.log);
        ASSERT_TRUE(wait_until([&] { return r.pending() == 0; }, 30)) << read_text(r.log);
    }
    std::cout << kills << " kills, " << in_the_window
              << " of them between the central commit and marking the entries sent\n";
    EXPECT_GE(kills, 20);

    // Read-only: the sites go on and catch up once it takes writes again.
    pg.psql("ALTER DATABASE tlsmon SET default_transaction_read_only = on", "postgres");
    pg.psql(
        "SELECT count(pg_terminate_backend(pid)) FROM pg_stat_activity WHERE datname ="
        " 'tlsmon' AND pid <> pg_backend_pid()",
        "postgres");
    for (int k = kBefore + kOutage; k < kEpochs; ++k) feed_all(k);
    ASSERT_TRUE(all_processed(kEpochs));
    for (auto& r : sites) {
        SCOPED_TRACE(r.name);
        ASSERT_TRUE(wait_until([&] { return r.forward_alarm() == "unack"; }, 30))
            << read_text(r.log);
        EXPECT_NE(sql(r.db, "SELECT last_error AS e FROM central_forward")
                      .at(0)
                      .at("e")
                      .get<std::string>()
                      .find("read-only transaction"),
                  std::string::npos);
    }
    pg.psql("ALTER DATABASE tlsmon RESET default_transaction_read_only", "postgres");
    for (auto& r : sites) {
        SCOPED_TRACE(r.name);
        ASSERT_TRUE(wait_until([&] { return r.forward_alarm() == "rtn_unack"; }, 120))
            << read_text(r.log);
        ASSERT_TRUE(wait_until([&] { return r.pending() == 0; }, 30)) << read_text(r.log);
        r.daemon->signal(SIGTERM);
        EXPECT_EQ(r.daemon->wait(60), 0) << read_text(r.log);
        EXPECT_EQ(sql(r.db, "SELECT count(*) AS n FROM outbox WHERE kind <> 'system_event'")
                      .at(0)
                      .at("n"),
                  0);
    }
    // Nothing missing, nothing doubled, in every table, for every site.
    for (const auto& r : sites) expect_same(pg, r);
    // In order: each site's cursor is its last entry, and its epochs arrived in the order
    // they were processed (site_seq grows with the acquisition time).
    EXPECT_EQ(pg.psql("SELECT count(*) FROM (SELECT site_id, acquired, site_seq, lag(site_seq)"
                      " OVER (PARTITION BY site_id ORDER BY acquired) AS before FROM"
                      " tlsmon.epochs) x WHERE site_seq < before"),
              "0\n");
}

}  // namespace
}  // namespace tlsmon::test::e2e
