// Campaigns on the dashboard: the daemon takes a simulated walk (in its SLAM's own frame) and
// its reference from the ingest folder and stores the campaign; the API answers what the
// database holds (read with the sqlite3 program), validated against docs/openapi.yaml; Debian's
// chromium, headless, shows the list and the campaign's page with every registered segment
// drawn (an arrow, or a cross where the view's directions are not observed) over the points.
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/support/dashboard_browser.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/modbus_client.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test::e2e {
namespace {

json get(int port, const std::string& path) {
    const auto r =
        shell("curl -s -f -m 20 " + quoted("http://127.0.0.1:" + std::to_string(port) + path));
    if (r.status != 0) throw std::runtime_error("curl " + path + ": " + r.output);
    return json::parse(r.output);
}

TEST(CampaignDashboard, TheApiAndTheBrowserShowTheStoredCampaign) {
    TempDir tmp("campaign-dashboard");
    const fs::path walk = tmp.path() / "walk", run = tmp.path() / "run";
    const auto sim = shell(std::string(TLSMON_BINARY) +
                           " simulate --preset small --campaign linear --pulse-rate 10000 --seed 3"
                           " --slam-frame --out " +
                           quoted(walk.string()));
    ASSERT_EQ(sim.status, 0) << sim.output;
    fs::create_directories(run / "ingest");
    const int port = free_tcp_port();
    write_text(
        run / "tlsmon.toml",
        "[station]\nname = \"bridge\"\n"
        "[paths]\ningest = \"ingest\"\ndatabase = \"tlsmon.sqlite\"\n"
        "archive = \"archive\"\nquarantine = \"quarantine\"\n"
        "[ingest]\narchive = \"move\"\nstable_seconds = 0\n"
        "[meteo]\nwait_seconds = 0\n"
        "[http]\nenabled = true\nport = " +
            std::to_string(port) +
            "\n"
            "[[instrument]]\nname = \"backpack\"\nkind = \"pls\"\npattern = \"pls_*.ply\"\n");
    fs::copy_file(walk / "reference.ply", run / "ingest/reference.ply");
    fs::copy_file(walk / "campaign.ply", run / "ingest/pls_walk.ply");
    const fs::path db = run / "tlsmon.sqlite", log = run / "daemon.log";
    DaemonProcess daemon(run / "tlsmon.toml", log);
    const auto stored = [&] {
        try {  // the file may exist before its tables
            return fs::exists(db) &&
                   sql(db, "SELECT count(*) AS n FROM campaigns").at(0).at("n").get<int>() == 1;
        } catch (const std::runtime_error&) {
            return false;
        }
    };
    ASSERT_TRUE(wait_until(stored, 180)) << read_text(log);

    // The API against the database.
    const json list = get(port, "/api/v1/campaigns");
    ASSERT_EQ(list.size(), 1u);
    const json row = sql(db, "SELECT id, points, segments, coarse, coarse_planes FROM campaigns");
    EXPECT_EQ(list[0]["id"], row[0]["id"]);
    EXPECT_EQ(list[0]["points"], row[0]["points"]);
    EXPECT_EQ(list[0]["coarse"], "planes");
    EXPECT_EQ(list[0]["coarse_planes"], row[0]["coarse_planes"]);
    const int id = row[0]["id"];
    const json one = get(port, "/api/v1/campaigns/" + std::to_string(id));
    EXPECT_EQ(one["segments"].size(), row[0]["segments"].get<std::size_t>());
    ASSERT_EQ(one["campaign"]["frame"].size(), 16u);
    EXPECT_EQ(one["campaign"]["frame"][15], 1.0);
    const json kept =
        sql(db, "SELECT count FROM campaign_points WHERE campaign_id = " + std::to_string(id));
    ASSERT_EQ(kept.size(), 1u);
    const std::size_t total = kept[0]["count"];
    const json points = get(port, "/api/v1/campaigns/" + std::to_string(id) + "/points?max=5000");
    EXPECT_EQ(points["total"], total);
    EXPECT_LE(points["shown"].get<std::size_t>(), 5000u);
    EXPECT_GT(points["shown"].get<std::size_t>(), 2500u);
    EXPECT_EQ(points["x"].size(), points["shown"].get<std::size_t>());
    EXPECT_EQ(points["c2c_m"].size(), points["shown"].get<std::size_t>());

    const auto openapi =
        shell("/usr/bin/python3 " +
              quoted(std::string(TLSMON_SOURCE_DIR) + "/tests/web/openapi_check.py") + " " +
              quoted(std::string(TLSMON_SOURCE_DIR) + "/docs/openapi.yaml") + " " +
              quoted("http://127.0.0.1:" + std::to_string(port)) + " " + std::to_string(id));
    EXPECT_EQ(openapi.status, 0) << openapi.output;

    // The pages in a real browser.
    const fs::path artifacts = browser_artifacts("campaign-dashboard");
    const json seen =
        dashboard_browser("campaign " + quoted("http://127.0.0.1:" + std::to_string(port)) + " " +
                              quoted(artifacts.string()) + " " + std::to_string(id),
                          artifacts);
    for (const auto& [page, errors] : seen["errors"].items())
        EXPECT_TRUE(errors.empty()) << page << ": " << errors.dump();
    ASSERT_EQ(seen["list"].size(), 1u);
    EXPECT_EQ(seen["list"][0]["link"], "/campaigns/" + std::to_string(id));
    const json& page = seen["page"];
    EXPECT_NE(page["title"].get<std::string>().find("Campaign " + std::to_string(id)),
              std::string::npos);
    EXPECT_EQ(page["views"], json::array({"plan", "elevation"}));
    EXPECT_EQ(page["segments"], one["segments"].size());
    // Every k-th of the kept points, at most 60 000.
    const std::size_t k = (total + 59999) / 60000;
    EXPECT_EQ(page["drawn"]["points"].get<std::size_t>(), (total + k - 1) / k);
    // In plan, an arrow for each registered segment that observes x or y, a cross for the rest.
    int arrows = 0, crosses = 0;
    for (const auto& s : one["segments"]) {
        if (s["outcome"] != "registered" || s["centroid"].is_null()) continue;
        const bool seen_xy = !s["t"][0].is_null() || !s["t"][1].is_null();
        (seen_xy ? arrows : crosses) += 1;
    }
    EXPECT_GT(arrows, 2);
    EXPECT_EQ(page["drawn"]["arrows"], arrows);
    EXPECT_EQ(page["drawn"]["crosses"], crosses);
    EXPECT_NE(page["frame"].get<std::string>().find("found on"), std::string::npos)
        << page["frame"];
}

}  // namespace
}  // namespace tlsmon::test::e2e
