// Campaign epochs end to end: the daemon takes a file of an [[instrument]] (its pattern) from
// the ingest folder, compares it with the reference epoch that came in the same batch, stores
// it with its segments in the real SQLite file apart from the station's epochs, and archives
// it; the stored segments are what the one-shot `tlsmon campaign compare` writes for the same
// two files. The same bytes again are known (`tlsmon campaign add` and the daemon); a cloud
// that does not overlap the reference is refused by the command and quarantined with its
// reason by the daemon, nothing stored.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/ply_writer.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/sha256.hpp"
#include "tests/support/csv_cells.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using tlsmon::test::CommandRun;
using tlsmon::test::run_tlsmon;

nlohmann::json json_of(const std::string& args) {
    const CommandRun r = run_tlsmon(args + " --format json", false);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.out;
    return nlohmann::json::parse(r.out);
}

TEST(CampaignEpochs, TheDaemonStoresAnInstrumentsFileApartFromTheStationAsTheCommandComputesIt) {
    const tlsmon::test::TempDir dir("campaign-epochs");
    const CommandRun sim =
        run_tlsmon("simulate --preset small --campaign linear --pulse-rate 10000 --seed 3 --out " +
                   (dir / "walk").string());
    ASSERT_EQ(sim.status, 0) << sim.out;
    fs::create_directories(dir / "ingest");
    fs::copy_file(dir / "walk/reference.ply", dir / "ingest/reference.ply");
    fs::copy_file(dir / "walk/campaign.ply", dir / "ingest/pls_walk.ply");
    const std::string campaign_sha = tlsmon::sha256_file(dir / "walk/campaign.ply");
    const fs::path config = dir / "site.toml";
    tlsmon::test::write_file(config,
                             "[station]\nname = \"bridge\"\n"
                             "[paths]\ningest = \"ingest\"\ndatabase = \"tlsmon.sqlite\"\n"
                             "archive = \"archive\"\nquarantine = \"quarantine\"\n"
                             "[ingest]\narchive = \"move\"\nstable_seconds = 0\n"
                             "[meteo]\nwait_seconds = 0\n"
                             "[[instrument]]\nname = \"backpack\"\nkind = \"pls\"\n"
                             "range_sigma = 0.02\npattern = \"pls_*.ply\"\n");
    const CommandRun run = run_tlsmon("run --once --config " + config.string());
    ASSERT_EQ(run.status, 0) << run.out;

    // The station has one epoch, the reference; the campaign is not one of its epochs.
    const auto epochs = json_of("query epochs --config " + config.string());
    ASSERT_EQ(epochs.size(), 1u) << epochs.dump();
    EXPECT_EQ(fs::path(epochs[0]["file"].get<std::string>()).filename(), "reference.ply");

    const auto campaigns = json_of("query campaigns --config " + config.string());
    ASSERT_EQ(campaigns.size(), 1u) << run.out;
    const auto& c = campaigns[0];
    EXPECT_EQ(c["instrument"], "backpack");
    EXPECT_EQ(c["kind"], "pls");
    EXPECT_EQ(c["sha256"], campaign_sha);
    EXPECT_EQ(c["reference_epoch"], epochs[0]["epoch"]);
    const auto cloud = tlsmon::read_scans(dir / "walk/campaign.ply");
    EXPECT_EQ(c["points"].get<std::size_t>(), cloud.at(0).size());
    // The walk's linear drift (20 mm and 0.5 mrad by its end) is found, as by the command.
    EXPECT_EQ(c["segments_differ"], true);
    EXPECT_LT(c["test_p"].get<double>(), 0.05);
    EXPECT_GT(c["registered_segments"].get<int>(), 3);
    EXPECT_LT(c["c2c_mean_m"].get<double>(), 0.05);
    // Archived under its own name, gone from the ingest folder.
    const fs::path stored = c["file"].get<std::string>();
    EXPECT_EQ(stored, dir / "archive/pls_walk.ply");
    EXPECT_TRUE(fs::exists(stored));
    EXPECT_FALSE(fs::exists(dir / "ingest/pls_walk.ply"));
    EXPECT_NE(run.out.find("campaign 1 of instrument 'backpack'"), std::string::npos) << run.out;

    // The stored segments are the one-shot command's on the same files.
    const CommandRun compare =
        run_tlsmon("campaign compare " + (dir / "walk/reference.ply").string() + " " +
                   (dir / "walk/campaign.ply").string() + " --out " + (dir / "one-shot").string());
    ASSERT_EQ(compare.status, 0) << compare.out;
    const CommandRun query = run_tlsmon(
        "query campaign-segments --campaign 1 --format csv --config " + config.string(), false);
    ASSERT_EQ(query.status, 0) << query.out;
    const auto stored_rows = tlsmon::test::csv_cells(query.out);
    const auto command_rows =
        tlsmon::test::csv_cells(tlsmon::test::read_file(dir / "one-shot/segments.csv"));
    ASSERT_EQ(stored_rows.size(), command_rows.size());
    ASSERT_EQ(stored_rows.size(), std::size_t(c["segments"].get<int>()) + 1);
    EXPECT_EQ(stored_rows[0], command_rows[0]);
    for (std::size_t i = 1; i < stored_rows.size(); ++i) {
        ASSERT_EQ(stored_rows[i].size(), command_rows[i].size()) << i;
        for (std::size_t k = 0; k < stored_rows[i].size(); ++k) {
            const std::string& a = stored_rows[i][k];
            const std::string& b = command_rows[i][k];
            char* end = nullptr;
            const double x = std::strtod(a.c_str(), &end);
            if (a.empty() || *end != '\0') {
                EXPECT_EQ(a, b) << stored_rows[0][k] << " of segment " << i - 1;
            } else {
                EXPECT_NEAR(x, std::stod(b), 1e-9 * std::max(1.0, std::abs(x)))
                    << stored_rows[0][k] << " of segment " << i - 1;
            }
        }
    }

    // The same bytes again: known, not compared twice, by the command and by the daemon.
    const CommandRun again = run_tlsmon("campaign add " + stored.string() +
                                        " --instrument backpack --config " + config.string());
    EXPECT_EQ(again.status, 0) << again.out;
    EXPECT_NE(again.out.find("is campaign 1 already"), std::string::npos) << again.out;
    fs::copy_file(dir / "walk/campaign.ply", dir / "ingest/pls_copy.ply");
    const CommandRun rerun = run_tlsmon("run --once --config " + config.string());
    ASSERT_EQ(rerun.status, 0) << rerun.out;
    EXPECT_NE(rerun.out.find("is campaign 1 already"), std::string::npos) << rerun.out;
    EXPECT_TRUE(fs::exists(dir / "ingest/pls_copy.ply"));
    EXPECT_EQ(json_of("query campaigns --config " + config.string()).size(), 1u);
    EXPECT_EQ(json_of("query epochs --config " + config.string()).size(), 1u);

    // A cloud a kilometre away: the command refuses it, the daemon quarantines it with the
    // reason; nothing is stored.
    std::vector<Eigen::Vector3d> far;
    for (int i = 0; i < 5000; ++i) far.emplace_back(1000.0 + 0.01 * (i % 70), 0.01 * (i / 70), 0);
    tlsmon::write_ply(dir / "far.ply", far, {});
    const CommandRun refused = run_tlsmon("campaign add " + (dir / "far.ply").string() +
                                          " --instrument backpack --config " + config.string());
    EXPECT_EQ(refused.status, 1) << refused.out;
    const CommandRun unknown = run_tlsmon("campaign add " + (dir / "far.ply").string() +
                                          " --instrument drone --config " + config.string());
    EXPECT_EQ(unknown.status, 1);
    EXPECT_NE(unknown.out.find("no [[instrument]] named 'drone'"), std::string::npos)
        << unknown.out;
    EXPECT_NE(unknown.out.find("it has backpack"), std::string::npos) << unknown.out;
    fs::copy_file(dir / "far.ply", dir / "ingest/pls_far.ply");
    const CommandRun quarantine = run_tlsmon("run --once --config " + config.string());
    ASSERT_EQ(quarantine.status, 0) << quarantine.out;
    EXPECT_TRUE(fs::exists(dir / "quarantine/pls_far.ply")) << quarantine.out;
    const std::string reason = tlsmon::test::read_file(dir / "quarantine/pls_far.ply.reason.txt");
    EXPECT_NE(reason.find("campaign not compared"), std::string::npos) << reason;
    EXPECT_EQ(json_of("query campaigns --config " + config.string()).size(), 1u);
    EXPECT_EQ(json_of("query epochs --config " + config.string()).size(), 1u);
    const CommandRun missing =
        run_tlsmon("query campaign-segments --campaign 7 --config " + config.string());
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.out.find("no campaign 7"), std::string::npos) << missing.out;
}

}  // namespace
