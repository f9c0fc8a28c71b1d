// The central database (docs/central.md) on a real PostgreSQL 15 started by the test: its
// migrations, a site's outbox forwarded into it and compared with the site's SQLite file
// (psql against sqlite3), a batch sent twice, and what one site's credential may not do.
#include <gtest/gtest.h>

#include <map>

#include "central/central_forward.hpp"
#include "tests/support/central_fixtures.hpp"

namespace tlsmon::test {
namespace {

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

// sslmode = verify-full: the server's certificate must be signed by sslrootcert and name the
// host; a site that trusts another CA refuses the server.
TEST(CentralDatabase, VerifyFullAcceptsOnlyTheServerItsAuthoritySigned) {
    Central central(true);
    CentralTarget t;
    t.url = central.pg.url(site_role("a"));
    t.password_file = central.password_file("a");
    t.sslmode = "verify-full";
    t.sslrootcert = central.pg.ca_certificate();
    PgConnection c = PgConnection::open(t);
    EXPECT_EQ(
        *c.exec("SELECT ssl::text FROM pg_stat_ssl WHERE pid = pg_backend_pid()").rows.at(0).at(0),
        "true");
    t.sslrootcert = central.pg.other_ca_certificate();
    try {
        PgConnection::open(t);
        FAIL() << "a server signed by another authority was accepted";
    } catch (const CentralError& e) {
        EXPECT_NE(std::string(e.what()).find("certificate verify failed"), std::string::npos)
            << e.what();
        EXPECT_EQ(std::string(e.what()).find("pw-a"), std::string::npos) << "the password shown";
    }
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
