// The central database (docs/central.md) on a real PostgreSQL 15 started by the test: its
// migrations, a site's outbox forwarded into it and compared with the site's SQLite file
// (psql against sqlite3), a batch sent twice, and what one site's credential may not do.
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "central/central_forward.hpp"
#include "central/central_schema.hpp"
#include "central/central_sites.hpp"
#include "tests/storage/fake_sha256.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/postgres_cluster.hpp"

namespace tlsmon::test {
namespace {

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) out.push_back(l);
    return out;
}

struct Central {
    PostgresCluster pg;
    TempDir dir{"central"};
    CentralTarget admin;
    Central() {
        admin.url = pg.url("postgres");
        admin.password_file = pg.admin_password_file();
        PgConnection c = PgConnection::open(admin);
        migrate_central(c);
        for (const char* site : {"a", "b"}) {
            write_text(password_file(site), std::string("pw-") + site + "\n");
            add_site(c, site, std::string("bridge ") + site, std::string("pw-") + site);
        }
    }
    fs::path password_file(const std::string& site) const { return dir / (site + ".pw"); }
    PgConnection as_site(const std::string& site) const {
        CentralTarget t;
        t.url = pg.url(site_role(site));
        t.password_file = password_file(site);
        return PgConnection::open(t);
    }
};

// A site database with forwarding on and three epochs, the last in the next month.
struct SiteDatabase {
    TempDir dir{"site"};
    EpochDatabase db = EpochDatabase::open(dir / "site.sqlite", EpochDatabase::Mode::read_write);
    SiteDatabase() {
        db.site().upsert_zone("pier", "{}");
        db.site().upsert_zone("deck", "{}");
        db.alarms().upsert_rule({0, "pier high", "pier", "m3c2_median_m", "{}", true});
        db.central_outbox().set_enabled(true);
        const UtcSeconds jan31 = parse_utc("2027-01-31T23:30:00Z");
        for (int k = 0; k < 3; ++k) commit(k, jan31 + 900 * k, 0.001 * k + 1.0 / 3e3);
    }
    void commit(int k, UtcSeconds t, double v) {
        const auto id = db.epochs().insert({fake_sha256(k + 1), t, "/ingest/s.ptx", 10, {}}).id;
        db.epochs().claim(id);
        EpochResults r;
        RegistrationRow reg;
        reg.method = "targets-helmert";
        reg.rms_m = 0.0007 + k * 1e-5;
        reg.accepted = true;
        reg.parameters = std::array<double, 6>{1e-6, 2e-6, 3e-6, 1e-3, 2e-3, 3e-3};
        reg.sigmas = std::array<double, 6>{1e-7, 1e-7, 1e-7, 1e-4, 1e-4, 1e-4};
        r.registration = reg;
        r.zone_results = {{"pier", "m3c2_median_m", v, 0.0011, 800, true},
                          {"deck", "m3c2_median_m", -v / 7, std::nullopt, 300, false}};
        r.alarm_events = {{t, "pier high", "raise", "alarm", v, id, "over 5 mm", "rule"}};
        r.system_events = {{t, "info", "epoch_done", "done", id}};
        db.results().commit(id, r);
    }
    fs::path path() const { return dir / "site.sqlite"; }
};

TEST(CentralDatabase, MigratedOnceWithMonthlyPartitionsAndRowLevelSecurity) {
    Central central;
    PgConnection c = PgConnection::open(central.admin);
    EXPECT_EQ(central_schema_version(c), static_cast<int>(central_migrations().size()));
    EXPECT_TRUE(migrate_central(c).empty()) << "a second migrate applied something";
    EXPECT_EQ(central.pg.psql("SELECT string_agg(c.relname, ',' ORDER BY c.relname) FROM"
                              " pg_partitioned_table p JOIN pg_class c ON c.oid = p.partrelid"),
              "alarm_events,epochs,registrations,system_events,zone_results\n");
    EXPECT_EQ(central.pg.psql("SELECT count(*) FROM pg_class c JOIN pg_namespace n ON"
                              " n.oid = c.relnamespace WHERE n.nspname = 'tlsmon' AND"
                              " c.relrowsecurity"),
              "7\n");
}

TEST(CentralDatabase, ForwardedRowsEqualTheSiteDatabaseAndABatchSentTwiceChangesNothing) {
    Central central;
    SiteDatabase site;
    const auto entries = site.db.central_outbox().pending(1000);
    ASSERT_EQ(entries.size(), 18u);
    const std::string source = site.db.central_outbox().state().database_id;
    PgConnection a = central.as_site("a");
    const std::span<const OutboxEntry> all(entries);
    EXPECT_EQ(forward_batch(a, source, all.first(7)), entries[6].seq);
    EXPECT_EQ(forward_batch(a, source, all.subspan(7)), entries.back().seq);
    const std::string counts =
        "SELECT (SELECT count(*) FROM tlsmon.epochs) || ' ' || (SELECT count(*) FROM"
        " tlsmon.registrations) || ' ' || (SELECT count(*) FROM tlsmon.zone_results) || ' ' ||"
        " (SELECT count(*) FROM tlsmon.alarm_events) || ' ' || (SELECT count(*) FROM"
        " tlsmon.system_events) || ' ' || (SELECT count(*) FROM tlsmon.zone_latest)";
    EXPECT_EQ(central.pg.psql(counts), "3 3 6 3 3 2\n");
    // The site crashed between the central commit and marking the entries sent: the same
    // entries again (and overlapping) leave every table as it was.
    forward_batch(a, source, all.first(12));
    forward_batch(a, source, all);
    EXPECT_EQ(central.pg.psql(counts), "3 3 6 3 3 2\n");
    // Two months, so two partitions of each table hold rows.
    EXPECT_EQ(central.pg.psql("SELECT count(DISTINCT tableoid) FROM tlsmon.zone_results"), "2\n");

    // Zone results: psql against sqlite3, value by value to the bit.
    std::map<std::string, double> site_values, central_values;
    for (const auto& row : e2e::sql(site.path(),
                                    "SELECT z.name || '|' || q.name || '|' || r.acquired || '|' ||"
                                    " e.sha256 AS k, printf('%!.17g', r.value) AS v FROM"
                                    " zone_results r JOIN zones z ON z.id = r.zone_id JOIN"
                                    " quantities q ON q.id = r.quantity_id JOIN epochs e ON"
                                    " e.id = r.epoch_id"))
        site_values[row.at("k")] = std::stod(row.at("v").get<std::string>());
    for (const auto& l : lines(central.pg.psql(
             "SELECT zone || '|' || quantity || '|' || extract(epoch FROM acquired)::bigint ||"
             " '|' || sha256, value FROM tlsmon.zone_results WHERE site_id = (SELECT id FROM"
             " tlsmon.sites WHERE name = 'a')"))) {
        const auto bar = l.rfind('|');
        central_values[l.substr(0, bar)] = std::stod(l.substr(bar + 1));
    }
    EXPECT_EQ(central_values, site_values);
    // The latest value of each zone is its last epoch's.
    EXPECT_EQ(central.pg.psql("SELECT zone || ' ' || sha256 FROM tlsmon.zone_latest ORDER BY zone"),
              "deck " + fake_sha256(3) + "\npier " + fake_sha256(3) + "\n");
    EXPECT_EQ(central.pg.psql("SELECT forwarded_seq, entries FROM tlsmon.site_cursors"),
              std::to_string(entries.back().seq) + "|" + std::to_string(18 + 12 + 18) + "\n");
}

TEST(CentralDatabase, ASiteCannotWriteOrSeeAnotherSitesRows) {
    Central central;
    SiteDatabase site;
    const auto entries = site.db.central_outbox().pending(1000);
    {
        PgConnection b = central.as_site("b");
        forward_batch(b, "site-b-db", entries);
    }
    const std::string b_id =
        lines(central.pg.psql("SELECT id FROM tlsmon.sites WHERE name = 'b'"))[0];
    const auto pw = central.password_file("a");
    const std::string role = site_role("a");
    // Inserting a row in b's name: refused by row-level security.
    auto r = central.pg.psql_as(role, pw,
                                "INSERT INTO tlsmon.zone_results VALUES (" + b_id +
                                    ", 'pier', 'm3c2_median_m', '2027-01-31T23:30Z', '" +
                                    fake_sha256(9) + "', 1, NULL, 1, true)");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("row-level security"), std::string::npos) << r.output;
    // Changing b's epochs: b's rows are invisible to a, so nothing changes.
    r = central.pg.psql_as(role, pw, "UPDATE tlsmon.epochs SET status = 'failed'");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(central.pg.psql("SELECT count(*) FROM tlsmon.epochs WHERE status = 'done'"), "3\n");
    // Deleting or updating results: no site has the privilege at all.
    r = central.pg.psql_as(role, pw, "DELETE FROM tlsmon.zone_results");
    EXPECT_NE(r.output.find("permission denied"), std::string::npos) << r.output;
    r = central.pg.psql_as(role, pw, "UPDATE tlsmon.zone_results SET value = 0");
    EXPECT_NE(r.output.find("permission denied"), std::string::npos) << r.output;
    // A partition directly, past the parent's policies: no privilege either.
    r = central.pg.psql_as(role, pw, "SELECT count(*) FROM tlsmon.zone_results_2027_01");
    EXPECT_NE(r.output.find("permission denied"), std::string::npos) << r.output;
    // Reading: a sees none of b's rows.
    r = central.pg.psql_as(role, pw, "SELECT count(*) FROM tlsmon.zone_results");
    EXPECT_EQ(r.output, "0\n");
    EXPECT_EQ(central.pg.psql("SELECT count(*) FROM tlsmon.zone_results"), "6\n");
    // A role that is no site cannot forward.
    central.pg.psql("CREATE ROLE intruder LOGIN PASSWORD 'x' IN ROLE tlsmon_site");
    write_text(central.dir / "x.pw", "x\n");
    r = central.pg.psql_as("intruder", central.dir / "x.pw",
                           "SELECT tlsmon.forward('s', '[]'::jsonb)");
    EXPECT_NE(r.output.find("is not a registered tlsmon site"), std::string::npos) << r.output;
}

TEST(CentralDatabase, ARotatedCredentialRefusesTheOldPassword) {
    Central central;
    {
        PgConnection c = PgConnection::open(central.admin);
        rotate_site_credential(c, "a", "new-pw-a");
    }
    EXPECT_THROW(central.as_site("a"), CentralError);
    write_text(central.password_file("a"), "new-pw-a\n");
    EXPECT_NO_THROW(central.as_site("a"));
    // The password never travelled or was stored in clear text.
    EXPECT_EQ(central.pg.psql("SELECT left(rolpassword, 13) FROM pg_authid WHERE rolname ="
                              " 'tlsmon_site_a'"),
              "SCRAM-SHA-256\n");
}

}  // namespace
}  // namespace tlsmon::test
