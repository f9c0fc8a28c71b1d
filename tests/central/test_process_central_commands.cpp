// The central database's commands (docs/central.md) as a user runs them, against a real
// PostgreSQL 15: `tlsmon central migrate|add-site`, and `tlsmon fleet` whose answers are
// compared with the central database (psql) and the site's file (sqlite3).
#include <gtest/gtest.h>

#include "central/central_forward.hpp"
#include "tests/support/central_fixtures.hpp"

namespace tlsmon::test {
namespace {

using e2e::json;
using e2e::quoted;

CommandResult tlsmon(const std::string& args) {
    return shell(std::string(TLSMON_BINARY) + " " + args);
}

TEST(CentralCommands, MigrateAndAddSiteFromTheCommandLine) {
    PostgresCluster pg;
    const std::string owner =
        quoted(pg.url("postgres")) + " --password-file " + pg.admin_password_file().string();
    auto r = tlsmon("central migrate " + owner);
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string n = std::to_string(central_migrations().size());
    EXPECT_NE(r.output.find("schema version " + n + ", " + n + " migration(s) applied"),
              std::string::npos)
        << r.output;
    r = tlsmon("central migrate " + owner);
    EXPECT_NE(r.output.find("(already up to date)"), std::string::npos) << r.output;

    // A password in the URL is refused, and not repeated.
    r = tlsmon("central migrate postgresql://postgres:admin-secret@127.0.0.1:" +
               std::to_string(pg.port()) + "/tlsmon");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("postgres:***@"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("admin-secret"), std::string::npos) << r.output;

    const TempDir dir("central-cli");
    write_text(dir / "site.pw", "site-secret\n");
    const std::string site_pw = " --site-password-file " + (dir / "site.pw").string();
    // A name the table refuses leaves no role behind.
    r = tlsmon("central add-site " + owner + " --name 'Pier 3'" + site_pw);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("sites_name_check"), std::string::npos) << r.output;
    EXPECT_EQ(pg.psql("SELECT count(*) FROM pg_roles WHERE rolname LIKE 'tlsmon_site_%'"), "0\n");

    r = tlsmon("central add-site " + owner + " --name a12-pier3 --location 'A12 km 34.2'" +
               site_pw);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(pg.psql("SELECT name || '|' || location || '|' || role_name FROM tlsmon.sites"),
              "a12-pier3|A12 km 34.2|tlsmon_site_a12-pier3\n");
    const auto login = pg.psql_as("tlsmon_site_a12-pier3", dir / "site.pw",
                                  "SELECT tlsmon.current_site() IS NOT NULL");
    EXPECT_EQ(login.output, "t\n");
}

TEST(FleetCommands, AnswersEqualTheCentralAndTheSiteDatabase) {
    Central central;
    SiteDatabase site;
    const auto entries = site.db.central_outbox().pending(1000);
    {
        PgConnection a = central.as_site("a");
        forward_batch(a, "a-db", entries);
        PgConnection b = central.as_site("b");
        forward_batch(b, "b-db", entries);
    }
    const std::string fleet = " --central " + quoted(central.pg.url("postgres")) +
                              " --password-file " + central.pg.admin_password_file().string() +
                              " --format json";
    auto r = tlsmon("fleet sites" + fleet);
    ASSERT_EQ(r.status, 0) << r.output;
    json j = json::parse(r.output);
    ASSERT_EQ(j.size(), 2u);
    EXPECT_EQ(j[0].at("site"), "a");
    EXPECT_EQ(j[0].at("location"), "bridge a");
    EXPECT_EQ(j[0].at("epochs"), 3);
    EXPECT_EQ(j[0].at("entries"), 18);
    EXPECT_EQ(j[0].at("newest_epoch"), "2027-02-01T00:00:00Z");

    // Every zone whose newest |value| is at least 2 mm: the pier of both sites (2.33 mm),
    // not the deck (0.33 mm).
    r = tlsmon("fleet status --min-abs 0.002" + fleet);
    ASSERT_EQ(r.status, 0) << r.output;
    j = json::parse(r.output);
    ASSERT_EQ(j.size(), 2u) << r.output;
    const double newest = std::stod(central.pg.psql(
        "SELECT value FROM tlsmon.zone_latest WHERE zone = 'pier' AND site_id = 1"));
    for (const auto& row : j) {
        EXPECT_EQ(row.at("zone"), "pier");
        EXPECT_EQ(row.at("value").get<double>(), newest);
        EXPECT_EQ(row.at("acquired"), "2027-02-01T00:00:00Z");
    }

    // One zone's series equals the site's file, value by value.
    r = tlsmon("fleet query series --site a --zone pier --quantity m3c2_median_m" + fleet);
    ASSERT_EQ(r.status, 0) << r.output;
    j = json::parse(r.output);
    const json local = e2e::sql(site.path(),
                                "SELECT r.value AS value, r.uncertainty AS u, r.n AS n FROM"
                                " zone_results r JOIN zones z ON z.id = r.zone_id WHERE z.name ="
                                " 'pier' ORDER BY r.acquired");
    ASSERT_EQ(j.size(), local.size());
    for (std::size_t k = 0; k < j.size(); ++k) {
        EXPECT_EQ(j[k].at("value").get<double>(), local[k].at("value").get<double>());
        EXPECT_EQ(j[k].at("uncertainty").get<double>(), local[k].at("u").get<double>());
        EXPECT_EQ(j[k].at("n"), local[k].at("n"));
    }
    // A window: only the last epoch.
    r = tlsmon(
        "fleet query series --site a --zone pier --quantity m3c2_median_m --from "
        "2027-02-01T00:00Z" +
        fleet);
    EXPECT_EQ(json::parse(r.output).size(), 1u) << r.output;

    r = tlsmon("fleet query alarms --site b" + fleet);
    ASSERT_EQ(r.status, 0) << r.output;
    j = json::parse(r.output);
    ASSERT_EQ(j.size(), 3u);
    EXPECT_EQ(j[0].at("site"), "b");
    EXPECT_EQ(j[0].at("rule"), "pier high");
    EXPECT_EQ(j[0].at("kind"), "raise");
    EXPECT_EQ(j[0].at("time"), "2027-01-31T23:30:00Z");

    // An analyst reads every site; a site's role is refused the fleet's view.
    central.pg.psql("CREATE ROLE anna LOGIN PASSWORD 'anna-pw' IN ROLE tlsmon_reader");
    write_text(central.dir / "anna.pw", "anna-pw\n");
    r = tlsmon("fleet status --central " + quoted(central.pg.url("anna")) + " --password-file " +
               (central.dir / "anna.pw").string() + " --format json");
    EXPECT_EQ(json::parse(r.output).size(), 4u) << r.output;
    r = tlsmon("fleet status --central " + quoted(central.pg.url(site_role("a"))) +
               " --password-file " + central.password_file("a").string() + " --format json");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("permission denied for table sites"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace tlsmon::test
