// The central database (docs/central.md) on a real PostgreSQL 15 started by the test: its
// migrations, a site's outbox forwarded into it and compared with the site's SQLite file
// (psql against sqlite3), a batch sent twice, what one site's credential may not do, and the
// per-core-point arrays forwarded only when asked, byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
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
              "alarm_events,core_point_arrays,epochs,registrations,system_events,zone_results\n");
    EXPECT_EQ(central.pg.psql("SELECT count(*) FROM pg_class c JOIN pg_namespace n ON"
                              " n.oid = c.relnamespace WHERE n.nspname = 'tlsmon' AND"
                              " c.relrowsecurity"),
              "8\n");
}

// A central database of version 1 with a month already partitioned: migration 2 gives that
// month its core point arrays' partition too (a new month gets it from ensure_month).
TEST(CentralDatabase, MigrationTwoPartitionsTheMonthsAlreadyThere) {
    PostgresCluster pg;
    CentralTarget admin;
    admin.url = pg.url("postgres");
    admin.password_file = pg.admin_password_file();
    PgConnection c = PgConnection::open(admin);
    c.exec("CREATE SCHEMA tlsmon");
    c.exec(
        "CREATE TABLE tlsmon.schema_migrations (version integer PRIMARY KEY, name text NOT"
        " NULL, applied timestamptz NOT NULL DEFAULT now())");
    c.exec_script(central_migrations()[0].sql);
    c.exec("INSERT INTO tlsmon.schema_migrations (version, name) VALUES (1, 'central')");
    c.exec("SELECT tlsmon.ensure_month('2027-01-15T00:00:00Z')");
    const std::string arrays_jan =
        "SELECT to_regclass('tlsmon.core_point_arrays_2027_01') IS NOT NULL";
    EXPECT_EQ(migrate_central(c), std::vector<int>{2});
    EXPECT_EQ(pg.psql(arrays_jan), "t\n");
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

// [central] forward_arrays: an epoch's arrays are queued only while it is on, at most 8 go in
// one batch, and they arrive byte for byte (psql's hex against sqlite3's), under the same
// row-level security as the results.
TEST(CentralDatabase, CorePointArraysAreForwardedOnlyWhenAskedAndArriveByteForByte) {
    Central central;
    SiteDatabase site;
    const auto commit_arrays = [&](int k, const char* t) {
        const auto id =
            site.db.epochs().insert({fake_sha256(k + 1), parse_utc(t), "/s", 10, {}}).id;
        site.db.epochs().claim(id);
        EpochResults r;
        for (int q = 0; q < 5; ++q) {
            CorePointArray a{"quantity_" + std::to_string(q), {}};
            for (int i = 0; i < 1000; ++i) a.values.push_back(float(k) + 1e-3F * float(i * q));
            a.values[7] = std::numeric_limits<float>::quiet_NaN();  // no distance there
            r.core_point_arrays.push_back(a);
        }
        site.db.results().commit(id, r);
    };
    const auto arrays_queued = [&] {
        return e2e::sql(site.path(),
                        "SELECT count(*) AS n FROM outbox WHERE kind ="
                        " 'core_point_array'")
            .at(0)
            .at("n")
            .get<int>();
    };
    commit_arrays(3, "2027-02-01T00:30:00Z");
    EXPECT_EQ(arrays_queued(), 0) << "forward_arrays is off";
    site.db.central_outbox().set_forward_arrays(true);
    EXPECT_TRUE(site.db.central_outbox().state().forward_arrays);
    commit_arrays(4, "2027-02-01T00:45:00Z");
    commit_arrays(5, "2027-02-01T01:00:00Z");
    ASSERT_EQ(arrays_queued(), 10);

    PgConnection a = central.as_site("a");
    const std::string source = site.db.central_outbox().state().database_id;
    int batches = 0;
    for (auto batch = site.db.central_outbox().pending(500); !batch.empty();
         batch = site.db.central_outbox().pending(500), ++batches) {
        EXPECT_LE(std::count_if(batch.begin(), batch.end(),
                                [](const OutboxEntry& e) { return e.kind == "core_point_array"; }),
                  8);
        site.db.central_outbox().mark_sent(forward_batch(a, source, batch), now_utc());
    }
    EXPECT_EQ(batches, 2);
    EXPECT_EQ(central.pg.psql("SELECT count(*) FROM tlsmon.core_point_arrays"), "10\n");
    std::map<std::string, std::string> site_hex, central_hex;
    for (const auto& row : e2e::sql(site.path(),
                                    "SELECT e.sha256 || '|' || a.quantity AS k, lower(hex(a.data))"
                                    " AS h FROM core_point_arrays a JOIN epochs e ON"
                                    " e.id = a.epoch_id WHERE e.acquired >= " +
                                        std::to_string(parse_utc("2027-02-01T00:45:00Z"))))
        site_hex[row.at("k")] = row.at("h");
    for (const auto& l :
         lines(central.pg.psql("SELECT sha256 || '|' || quantity, encode(data, 'hex') FROM"
                               " tlsmon.core_point_arrays"))) {
        const auto bar = l.rfind('|');
        central_hex[l.substr(0, bar)] = l.substr(bar + 1);
    }
    EXPECT_EQ(central_hex.size(), 10u);
    EXPECT_TRUE(central_hex == site_hex);
    // Site b sees none of them; a partition of this month was made for them.
    const auto r = central.pg.psql_as(site_role("b"), central.password_file("b"),
                                      "SELECT count(*) FROM tlsmon.core_point_arrays");
    EXPECT_EQ(r.output, "0\n");
    EXPECT_EQ(central.pg.psql("SELECT to_regclass('tlsmon.core_point_arrays_2027_02') IS NOT NULL"),
              "t\n");
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
