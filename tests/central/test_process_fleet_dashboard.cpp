// The fleet's page (`tlsmon fleet serve`, docs/central.md) on a real PostgreSQL 15: a site's
// outbox forwarded, the server run as an analyst (a tlsmon_reader role), its API refusing
// malformed parameters, and Debian's chromium (headless) showing every site and every zone
// quantity's newest value as psql reads them, and a clicked row's series as stored.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "central/central_forward.hpp"
#include "tests/support/central_fixtures.hpp"
#include "tests/support/dashboard_browser.hpp"
#include "tests/support/modbus_client.hpp"

namespace tlsmon::test {
namespace {

int http_status(const std::string& url) {
    const auto r = shell("curl -s -o /dev/null -w '%{http_code}' -m 10 '" + url + "'");
    return std::atoi(r.output.c_str());
}

TEST(FleetDashboard, TheBrowserShowsWhatTheCentralDatabaseHolds) {
    Central central;
    SiteDatabase site;
    {
        PgConnection a = central.as_site("a");
        forward_batch(a, site.db.central_outbox().state().database_id,
                      site.db.central_outbox().pending(1000));
    }
    central.pg.psql("CREATE ROLE analyst LOGIN PASSWORD 'analyst-pw' IN ROLE tlsmon_reader");
    write_text(central.dir / "analyst.pw", "analyst-pw\n");
    const int port = free_tcp_port();
    const std::string base = "http://127.0.0.1:" + std::to_string(port);
    const fs::path log = central.dir / "serve.log";
    ChildProcess server("exec " + std::string(TLSMON_BINARY) + " fleet serve --central " +
                            central.pg.url("analyst") + " --password-file " +
                            (central.dir / "analyst.pw").string() + " --port " +
                            std::to_string(port),
                        log);
    ASSERT_TRUE(wait_until([&] { return http_status(base + "/api/v1/fleet/sites") == 200; }, 30))
        << read_text(log);
    // Malformed parameters are refused, naming the parameter.
    EXPECT_EQ(http_status(base + "/api/v1/fleet/status?min_abs=lots"), 400);
    EXPECT_EQ(http_status(base + "/api/v1/fleet/series?site=a&zone=pier"), 400);
    EXPECT_EQ(http_status(base + "/api/v1/fleet/series?site=a&zone=pier&quantity=q&from=x"), 400);
    EXPECT_EQ(http_status(base + "/static/../../etc/passwd"), 404);

    const fs::path artifacts = browser_artifacts("fleet-dashboard");
    const auto seen =
        dashboard_browser("fleet " + base + " '" + artifacts.string() + "'", artifacts);
    for (const auto& [page, errors] : seen.at("errors").items())
        EXPECT_TRUE(errors.empty()) << page << ": " << errors.dump();
    // The sites: a with its three epochs, b with none.
    ASSERT_EQ(seen.at("sites").size(), 2u);
    EXPECT_EQ(seen.at("sites")[0][0], "a");
    EXPECT_EQ(seen.at("sites")[0][2], "3");
    EXPECT_EQ(seen.at("sites")[1][2], "0");
    // Every zone quantity's newest value, as psql reads tlsmon.zone_latest.
    std::map<std::string, double> stored;
    for (const auto& l :
         lines(central.pg.psql("SELECT s.name || ' ' || l.zone || ' ' || l.quantity, l.value FROM"
                               " tlsmon.zone_latest l JOIN tlsmon.sites s ON s.id = l.site_id")))
        stored[l.substr(0, l.rfind('|'))] = std::stod(l.substr(l.rfind('|') + 1));
    std::map<std::string, double> shown;
    for (const auto& r : seen.at("status"))
        shown[r.at("site").get<std::string>() + " " + r.at("zone").get<std::string>() + " " +
              r.at("quantity").get<std::string>()] = r.at("value").get<double>();
    EXPECT_EQ(shown, stored);
    // The clicked row's series: every epoch's value, in mm.
    const auto& series = seen.at("series");
    std::map<std::int64_t, double> values;
    for (const auto& l : lines(central.pg.psql(
             "SELECT extract(epoch FROM r.acquired)::bigint, r.value FROM tlsmon.zone_results r"
             " JOIN tlsmon.sites s ON s.id = r.site_id WHERE s.name = '" +
             series.at("site").get<std::string>() + "' AND r.zone = '" +
             series.at("zone").get<std::string>() + "' AND r.quantity = '" +
             series.at("quantity").get<std::string>() + "'")))
        values[std::stoll(l.substr(0, l.find('|')))] = std::stod(l.substr(l.find('|') + 1));
    ASSERT_EQ(series.at("rows").size(), values.size());
    for (const auto& row : series.at("rows")) {
        const auto t = std::llround(row[0].get<double>());
        ASSERT_TRUE(values.contains(t)) << t;
        EXPECT_NEAR(row[1].get<double>(), values.at(t) * 1e3, 1e-9);
    }
}

}  // namespace
}  // namespace tlsmon::test
