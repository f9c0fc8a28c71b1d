// `tlsmon vectors` and the daemon's vectors stage on the same two files: a strip of the
// `pier` scene (its lower 10 m and the targets, at 0.02°) written by `tlsmon simulate`, no
// thermal bending. `tlsmon run --once` stores the epochs with [vectors] on; the one-shot
// command with the same configuration prints the same zone rows to the last digit, and its
// per-area CSV holds vectors of about zero (the pier did not move) within their σ. Bad input:
// a window the kernel cannot use, a missing file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "formats/las_reader.hpp"
#include "tests/support/csv_cells.hpp"
#include "tests/support/independent_las.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using tlsmon::test::run_tlsmon;

void write(const fs::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

// The command's printed zone rows of `zone`: quantity -> (value, LoD95, n).
struct Printed {
    double value = NAN, lod = NAN;
    long n = 0;
};
std::map<std::string, Printed> printed_rows(const std::string& out, const std::string& zone) {
    std::map<std::string, Printed> rows;
    const std::regex line(
        "^" + zone + " (vector_[a-z_]+) = ([-0-9.e]+)(?: \\(LoD95 ([-0-9.e]+)\\))? n ([0-9]+)");
    std::istringstream in(out);
    for (std::string l; std::getline(in, l);) {
        std::smatch m;
        if (!std::regex_search(l, m, line)) continue;
        rows[m[1]] = {std::stod(m[2]), m[3].matched ? std::stod(m[3]) : NAN, std::stol(m[4])};
    }
    return rows;
}

TEST(VectorsCommand, OneShotReproducesTheDaemonOnAPierThatDidNotMove) {
    const tlsmon::test::TempDir dir("vectors");
    write(dir / "scene.toml",
          "preset = \"pier\"\n[scanner]\nelevation_max_deg = 12.0\nazimuth_step_deg = 0.02\n"
          "elevation_step_deg = 0.02\n[deformation]\nenabled = false\n");
    const auto sim = run_tlsmon("simulate --config " + (dir / "scene.toml").string() + " --out " +
                                (dir / "scans").string() + " --epochs 2");
    ASSERT_EQ(sim.status, 0) << sim.out;
    const fs::path config = dir / "site.toml";
    write(config, tlsmon::test::read_file(dir / "scans/site.toml") +
                      "\n[vectors]\nenabled = true\n"
                      "\n[paths]\ningest = \"scans\"\ndatabase = \"tlsmon.sqlite\"\narchive = "
                      "\"archive\"\nquarantine = \"quarantine\"\n\n[ingest]\narchive = "
                      "\"keep\"\nstable_seconds = 0\n");
    const auto run = run_tlsmon("run --once --config " + config.string());
    ASSERT_EQ(run.status, 0) << run.out;

    const std::string a = (dir / "scans/pier_20260601T060000Z.ptx").string();
    const std::string b = (dir / "scans/pier_20260601T061500Z.ptx").string();
    const fs::path csv = dir / "v.csv";
    const auto one = run_tlsmon("vectors " + a + " " + b + " --config " + config.string() +
                                " --out " + csv.string());
    ASSERT_EQ(one.status, 0) << one.out;
    EXPECT_NE(one.out.find("vectors.window = 1"), std::string::npos) << one.out;
    const auto rows = printed_rows(one.out, "pier_south_face");
    ASSERT_EQ(rows.size(), 7u) << one.out;
    EXPECT_GT(rows.at("vector_count").value, 10);
    for (const auto& [quantity, row] : rows) {
        const auto stored = run_tlsmon("query series --zone pier_south_face --quantity " +
                                           quantity + " --format json --config " + config.string(),
                                       false);
        ASSERT_EQ(stored.status, 0) << stored.out;
        const auto series = nlohmann::json::parse(stored.out);
        ASSERT_EQ(series.size(), 2u) << quantity;
        const auto& e = series[1];
        EXPECT_NEAR(e.at("value").get<double>(), row.value, 1e-12 + 1e-9 * std::abs(row.value))
            << quantity;
        if (std::isfinite(row.lod)) {
            EXPECT_NEAR(e.at("uncertainty").get<double>(), row.lod, 1e-12 + 1e-9 * row.lod)
                << quantity;
        }
        EXPECT_EQ(e.at("n").get<long>(), row.n) << quantity;
    }
    // The pier did not move: every component of the zone's vector within a millimetre.
    for (const char* q : {"vector_dx_m", "vector_dy_m", "vector_dz_m"})
        EXPECT_LT(std::abs(rows.at(q).value), 0.001) << q;

    // One CSV row per area, with its outcome; a measured area's vector has its σ.
    std::istringstream in(tlsmon::test::read_file(csv));
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header.rfind("area,supervoxel,zones,x_m,y_m,z_m,", 0), 0u) << header;
    int measured = 0;
    for (std::string l; std::getline(in, l);) measured += l.find(",measured") != std::string::npos;
    EXPECT_GE(measured, rows.at("vector_count").value);

    // `tlsmon export --map vectors`: every area at its centre, the stored vector and σ (float32)
    // of a measured one, NaN elsewhere; the same file read by tlsmon and by copc.js.
    const fs::path las = dir / "v.las";
    const auto exported = run_tlsmon("export --epoch 2 --map vectors --out " + las.string() +
                                     " --config " + config.string());
    ASSERT_EQ(exported.status, 0) << exported.out;
    const auto cells = tlsmon::test::csv_cells(tlsmon::test::read_file(csv));
    const tlsmon::LasPoints own = tlsmon::read_las_points(las);
    const nlohmann::json other = tlsmon::test::read_las_independently(las);
    ASSERT_EQ(own.xyz.size(), cells.size() - 1);
    ASSERT_EQ(own.attributes.size(), 7u);
    int exported_measured = 0;
    for (std::size_t k = 0; k < own.xyz.size(); ++k) {
        const auto& row = cells[k + 1];
        const bool is_measured = row.back() == "measured";
        exported_measured += is_measured;
        for (int c = 0; c < 3; ++c) {
            const double x = std::stod(row[std::size_t(3 + c)]);
            EXPECT_NEAR(own.xyz[k][c], x, 0.5e-6 + 1e-9) << k;
            EXPECT_NEAR(other.at("points").at(std::string(1, "XYZ"[c]))[k].get<double>(), x,
                        0.5e-6 + 1e-9);
            for (const std::size_t column : {std::size_t(9 + c), std::size_t(12 + c)}) {
                const auto& attribute = own.attributes[column - 9];
                const double value = attribute.values[k];
                const double theirs =
                    tlsmon::test::las_number(other.at("points").at(attribute.name)[k]);
                if (is_measured) {
                    EXPECT_EQ(value, double(float(std::stod(row[column])))) << attribute.name;
                    EXPECT_EQ(theirs, value) << attribute.name;
                } else {
                    EXPECT_TRUE(std::isnan(value) && std::isnan(theirs)) << attribute.name;
                }
            }
        }
    }
    EXPECT_EQ(exported_measured, measured);

    // Bad input: a clear error, exit 1, nothing written.
    const auto tiny =
        run_tlsmon("vectors " + a + " " + b + " --window 0 --out " + (dir / "x.csv").string());
    EXPECT_EQ(tiny.status, 1);
    EXPECT_NE(tiny.out.find("window"), std::string::npos) << tiny.out;
    const auto missing = run_tlsmon("vectors " + (dir / "missing.ptx").string() + " " + b +
                                    " --out " + (dir / "x.csv").string());
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.out.find("missing.ptx"), std::string::npos) << missing.out;
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

}  // namespace
