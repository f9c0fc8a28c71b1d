// Campaign epochs end to end: the daemon takes a file of an [[instrument]] (its pattern) from
// the ingest folder — a walk in its SLAM's own frame —, finds its frame on planes, compares it
// with the reference epoch that came in the same batch, stores it with its segments and its
// points in the real SQLite file apart from the station's epochs, and archives it; the stored
// segments are what the one-shot `tlsmon campaign compare` writes for the same two files, and
// the frame both found is the simulator's. The same bytes again are known (`tlsmon campaign add`
// and the daemon); a cloud that does not overlap the reference is refused by the command and
// quarantined with its reason by the daemon, nothing stored.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/las_reader.hpp"
#include "formats/ply_writer.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/sha256.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/csv_cells.hpp"
#include "tests/support/independent_las.hpp"
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
    const CommandRun sim = run_tlsmon(
        "simulate --preset small --campaign linear --pulse-rate 10000 --seed 3 "
        "--slam-frame --out " +
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
                             "range_sigma = 0.02\npattern = \"pls_*.ply\"\n"
                             // The pier's south face (simulator/scene.hpp: y = 45 m), fed by
                             // the campaign, and a rule on it.
                             "[campaign]\nzone_series = true\n"
                             "[[zone]]\nname = \"pier_south\"\nmin = [4.0, 44.5, -5.0]\n"
                             "max = [15.0, 45.5, 20.0]\nnormal = [0.0, -1.0, 0.0]\n"
                             "[[alarm.rule]]\nname = \"pier_south.shape\"\n"
                             "zone = \"pier_south\"\nquantity = \"campaign_c2c_median_m\"\n"
                             "alarm = { high = 0.010, low = -0.010 }\n");
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
    EXPECT_EQ(c["coarse"], "planes");
    EXPECT_GE(c["coarse_planes"].get<int>(), 4);
    // Archived under its own name, gone from the ingest folder.
    const fs::path stored = c["file"].get<std::string>();
    EXPECT_EQ(stored, dir / "archive/pls_walk.ply");
    EXPECT_TRUE(fs::exists(stored));
    EXPECT_FALSE(fs::exists(dir / "ingest/pls_walk.ply"));
    EXPECT_NE(run.out.find("campaign 1 of instrument 'backpack'"), std::string::npos) << run.out;

    // Its value on the pier's face is in the zone's series under its own quantity, named by
    // the campaign and with no epoch: the walk's drift is its segments', so no change of shape
    // is left. The rule watching it was evaluated at the campaign's time, and stays normal.
    const auto series = json_of(
        "query series --zone pier_south --quantity campaign_c2c_median_m "
        "--config " +
        config.string());
    ASSERT_EQ(series.size(), 1u) << series.dump();
    EXPECT_EQ(series[0]["datum"], "campaign 1");
    EXPECT_TRUE(series[0]["epoch"].is_null());
    EXPECT_GE(series[0]["n"].get<int>(), 30);
    const double lod95 = series[0]["uncertainty"].get<double>();
    EXPECT_GT(lod95, 0.0);
    EXPECT_LT(lod95, 0.005);
    EXPECT_LT(std::abs(series[0]["value"].get<double>()), 0.005) << series.dump();
    // The station's own series of the zone holds its epochs only.
    for (const auto& row : json_of("query series --zone pier_south --quantity m3c2_median_m "
                                   "--config " +
                                   config.string())) {
        EXPECT_EQ(row["epoch"], epochs[0]["epoch"]);
        EXPECT_EQ(row["datum"].get<std::string>().find("campaign"), std::string::npos);
    }
    {
        const auto db = tlsmon::EpochDatabase::open(dir / "tlsmon.sqlite",
                                                    tlsmon::EpochDatabase::Mode::read_only);
        const auto states = db.alarms().states();
        ASSERT_EQ(states.size(), 1u);
        EXPECT_EQ(states[0].rule, "pier_south.shape");
        EXPECT_EQ(states[0].state, "normal");
        EXPECT_EQ(states[0].value, series[0]["value"].get<double>());
        EXPECT_FALSE(states[0].epoch);
    }

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

    // The frame the command found (frame.txt, campaign → reference) is the simulator's
    // (campaign.truth.json, campaign → scene): M·F⁻¹ is the identity but for the drift's mean
    // pose (20 mm and 0.5 mrad at the walk's end).
    Eigen::Matrix4d M, F;
    std::ifstream frame_txt(dir / "one-shot/frame.txt");
    for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) ASSERT_TRUE(frame_txt >> M(r, k));
    const auto truth =
        nlohmann::json::parse(tlsmon::test::read_file(dir / "walk/campaign.truth.json"));
    for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k) F(r, k) = truth["frame"][r][k].get<double>();
    EXPECT_GT((F.topRightCorner<3, 1>()).norm(), 5.0);  // the walk starts 5 m or more away
    const Eigen::Matrix4d E = M * F.inverse();
    EXPECT_LT(Eigen::AngleAxisd(Eigen::Matrix3d(E.topLeftCorner<3, 3>())).angle(), 0.002);
    const Eigen::Vector3d start(truth["walk"][0][0].get<double>(),
                                truth["walk"][0][1].get<double>(),
                                truth["walk"][0][2].get<double>());
    EXPECT_LT(((E * start.homogeneous()).head<3>() - start).norm(), 0.03);

    // The points the daemon kept: thinned, in the reference's frame (within its extent), on
    // its surfaces (C2C), with their segments.
    const CommandRun points_run = run_tlsmon(
        "query campaign-points --campaign 1 --format csv --config " + config.string(), false);
    ASSERT_EQ(points_run.status, 0) << points_run.out;
    const auto points = tlsmon::test::csv_cells(points_run.out);
    // This sparse walk (10 000 pulses/s) has few points closer than the 5 cm voxels.
    ASSERT_GT(points.size(), 1000u);
    EXPECT_LT(points.size(), cloud.at(0).size());
    ASSERT_EQ(points[0], (std::vector<std::string>{"x_m", "y_m", "z_m", "segment", "c2c_dx_m",
                                                   "c2c_dy_m", "c2c_dz_m", "c2c_m"}));
    Eigen::AlignedBox3d extent;
    const auto reference_scans = tlsmon::read_scans(dir / "walk/reference.ply");
    for (const auto& p : reference_scans.at(0).xyz) extent.extend(p);
    extent.extend(extent.min() - Eigen::Vector3d::Constant(0.5));
    extent.extend(extent.max() + Eigen::Vector3d::Constant(0.5));
    std::size_t inside = 0, in_segments = 0;
    std::vector<double> c2c;
    for (std::size_t i = 1; i < points.size(); ++i) {
        const Eigen::Vector3d x(std::stod(points[i][0]), std::stod(points[i][1]),
                                std::stod(points[i][2]));
        inside += extent.contains(x);
        if (!points[i][7].empty()) c2c.push_back(std::stod(points[i][7]));
        in_segments += std::stoi(points[i][3]) >= 0;
    }
    const double n = double(points.size() - 1);
    EXPECT_GT(double(inside), 0.999 * n);
    // Their C2C as the whole cloud's (thinning keeps one point of each voxel, so the median of
    // the kept ones is near the cloud's), nearly every point with one.
    EXPECT_GT(double(c2c.size()), 0.95 * n);
    std::nth_element(c2c.begin(), c2c.begin() + long(c2c.size() / 2), c2c.end());
    const double median = c2c[c2c.size() / 2], cloud_median = c["c2c_median_m"].get<double>();
    EXPECT_GT(median, 0.7 * cloud_median);
    EXPECT_LT(median, 1.3 * cloud_median);
    EXPECT_GT(double(in_segments), 0.2 * n);
    EXPECT_LT(double(in_segments), n);  // the ground is in none

    // `tlsmon export` writes the same points as LAS 1.4 (read by tlsmon and by copc.js):
    // coordinates to 1 µm, segment and C2C vector as stored.
    const auto las = dir / "campaign.las";
    const CommandRun exported =
        run_tlsmon("export --campaign 1 --out " + las.string() + " --config " + config.string());
    ASSERT_EQ(exported.status, 0) << exported.out;
    const tlsmon::LasPoints own = tlsmon::read_las_points(las);
    const nlohmann::json other = tlsmon::test::read_las_independently(las);
    ASSERT_EQ(own.xyz.size(), points.size() - 1);
    ASSERT_EQ(own.attributes.size(), 5u);
    const auto& theirs = other.at("points");
    const auto cell = [](const std::string& text) {
        return text.empty() ? std::numeric_limits<double>::quiet_NaN() : std::stod(text);
    };
    // c2c_m is the length of the stored float32 vector, computed in double by both.
    const auto same = [](double a, double b) {
        return std::abs(a - b) <= 1e-12 * std::abs(b) || (std::isnan(a) && std::isnan(b));
    };
    for (std::size_t i = 1; i < points.size(); ++i) {
        const std::size_t k = i - 1;
        for (int a = 0; a < 3; ++a) {
            const double x = std::stod(points[i][std::size_t(a)]);
            ASSERT_NEAR(own.xyz[k][a], x, 0.5e-6 + 1e-9) << k;
            ASSERT_NEAR(theirs.at(std::string(1, "XYZ"[a]))[k].get<double>(), x, 0.5e-6 + 1e-9);
        }
        for (std::size_t col = 3; col < 8; ++col) {
            const double stored = cell(points[i][col]);
            const tlsmon::LasAttribute& attribute = own.attributes[col - 3];
            ASSERT_EQ(attribute.name, points[0][col]);
            ASSERT_TRUE(same(attribute.values[k], stored)) << attribute.name << " " << k;
            ASSERT_TRUE(same(tlsmon::test::las_number(theirs.at(attribute.name)[k]), stored))
                << attribute.name << " " << k;
        }
    }

    // The report lists it (its own section: not in the zone series).
    const CommandRun report = run_tlsmon("report --database " + (dir / "tlsmon.sqlite").string() +
                                         " --out " + (dir / "report").string());
    ASSERT_EQ(report.status, 0) << report.out;
    const std::string md = tlsmon::test::read_file(dir / "report/report.md");
    const auto section = md.find("## Campaigns");
    ASSERT_NE(section, std::string::npos) << md;
    EXPECT_NE(md.find("| 1 | ", section), std::string::npos) << md.substr(section);
    EXPECT_NE(
        md.find("found on " + std::to_string(c["coarse_planes"].get<int>()) + " planes", section),
        std::string::npos)
        << md.substr(section);
    EXPECT_NE(md.find("**no** (p", section), std::string::npos) << md.substr(section);

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
