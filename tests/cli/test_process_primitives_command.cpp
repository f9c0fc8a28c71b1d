// `tlsmon primitives` and the daemon's primitives stage on the same two files: a `round`
// scene (the 4 m column, its lower 11 m in view) written by `tlsmon simulate`, the column
// tilting (17.55″, 9.59″) — 20″ towards the north-east — from its second epoch on, no
// thermal bending. `tlsmon run --once` stores the epochs; the one-shot command with the same
// configuration prints and writes the same rows to the last digit; both against the truth
// file's axis tilt within their LoD. Bad input: no zone, a malformed --box, an unknown
// primitive in a [[zone]].
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using tlsmon::test::run_tlsmon;

void write(const fs::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

// zone,quantity,value,lod,n,significant rows by quantity.
std::map<std::string, std::vector<std::string>> csv_rows(const fs::path& csv) {
    std::istringstream in(tlsmon::test::read_file(csv));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "zone,quantity,value,lod,n,significant");
    std::map<std::string, std::vector<std::string>> out;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::istringstream fields(line);
        for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
        out[f.at(1)] = f;
    }
    return out;
}

TEST(PrimitivesCommand, OneShotReproducesTheDaemonAndFindsTheTilt) {
    const tlsmon::test::TempDir dir("primitives");
    write(dir / "scene.toml",
          "preset = \"round\"\n[scanner]\nelevation_max_deg = 12.0\n[deformation]\nenabled = "
          "false\n[events]\ntilt_epoch = 1\ntilt_arcsec = [17.55, 9.59]\n");
    const auto sim = run_tlsmon("simulate --config " + (dir / "scene.toml").string() + " --out " +
                                (dir / "scans").string() + " --epochs 2");
    ASSERT_EQ(sim.status, 0) << sim.out;
    const fs::path config = dir / "site.toml";
    write(config, tlsmon::test::read_file(dir / "scans/site.toml") +
                      "\n[paths]\ningest = \"scans\"\ndatabase = \"tlsmon.sqlite\"\narchive = "
                      "\"archive\"\nquarantine = \"quarantine\"\n\n[ingest]\narchive = "
                      "\"keep\"\nstable_seconds = 0\n");
    ASSERT_NE(tlsmon::test::read_file(config).find("primitive = \"cylinder\""), std::string::npos);
    const auto run = run_tlsmon("run --once --config " + config.string());
    ASSERT_EQ(run.status, 0) << run.out;

    const std::string a = (dir / "scans/round_20260601T060000Z.ptx").string();
    const std::string b = (dir / "scans/round_20260601T061500Z.ptx").string();
    const auto one = run_tlsmon("primitives " + a + " " + b + " --config " + config.string() +
                                " --out " + (dir / "p.csv").string());
    ASSERT_EQ(one.status, 0) << one.out;
    const auto rows = csv_rows(dir / "p.csv");
    ASSERT_EQ(rows.size(), 8u);
    for (const auto& [quantity, row] : rows) {
        const auto stored = run_tlsmon("query series --zone pier_column --quantity " + quantity +
                                           " --format json --config " + config.string(),
                                       false);
        ASSERT_EQ(stored.status, 0) << stored.out;
        const auto series = nlohmann::json::parse(stored.out);
        ASSERT_EQ(series.size(), 2u) << quantity;
        const auto& e = series[1];
        const double v = std::stod(row[2]);
        EXPECT_NEAR(e.at("value").get<double>(), v, 1e-12 + 1e-12 * std::abs(v)) << quantity;
        if (!row[3].empty()) {
            EXPECT_NEAR(e.at("uncertainty").get<double>(), std::stod(row[3]), 1e-12) << quantity;
        }
        EXPECT_EQ(e.at("n").get<std::int64_t>(), std::stoll(row[4])) << quantity;
        EXPECT_EQ(e.at("significant").get<bool>(), row[5] == "1") << quantity;
    }
    // Against the truth of the second epoch: the axis's lean, each component within its LoD.
    const auto truth = nlohmann::json::parse(
        tlsmon::test::read_file(dir / "scans/round_20260601T061500Z.truth.json"));
    const auto& tilt = truth.at("pier_axis").at("tilt_arcsec");
    for (int k = 0; k < 2; ++k) {
        const auto& row = rows.at(k == 0 ? "cylinder_lean_x_arcsec" : "cylinder_lean_y_arcsec");
        EXPECT_NEAR(std::stod(row[2]), tilt[k].get<double>(), std::stod(row[3])) << row[1];
        EXPECT_EQ(row[5], "1") << row[1];
    }
    EXPECT_EQ(rows.at("cylinder_tilt_arcsec")[5], "1");
    EXPECT_LT(std::abs(std::stod(rows.at("cylinder_radius_change_m")[2])), 1e-4);
    EXPECT_NE(one.out.find("pier_column: reference cylinder at (9.5"), std::string::npos)
        << one.out;

    // Bad input: a clear error, exit 1, nothing written.
    const auto none =
        run_tlsmon("primitives " + a + " " + b + " --out " + (dir / "x.csv").string());
    EXPECT_EQ(none.status, 1);
    EXPECT_NE(none.out.find("give --config (zones naming a primitive) or --box and --kind"),
              std::string::npos)
        << none.out;
    const auto box = run_tlsmon("primitives " + a + " " + b + " --box 1 2 3 0 0 0 --out " +
                                (dir / "x.csv").string());
    EXPECT_EQ(box.status, 1);
    EXPECT_NE(box.out.find("--box: expected x_min y_min z_min x_max y_max z_max"),
              std::string::npos)
        << box.out;
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
    write(dir / "cone.toml",
          "[[zone]]\nname = \"c\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
          "primitive = \"cone\"\n");
    const auto cone = run_tlsmon("check-config " + (dir / "cone.toml").string());
    EXPECT_NE(cone.status, 0);
    EXPECT_NE(cone.out.find("primitive"), std::string::npos) << cone.out;
    EXPECT_NE(cone.out.find("unknown primitive 'cone' (expected plane, cylinder or sphere)"),
              std::string::npos)
        << cone.out;
}

}  // namespace
