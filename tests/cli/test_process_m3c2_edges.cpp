// M3C2's strays at a face's edges, end to end (docs/m3c2.md, "Stray points at a face's edge"):
// two scans of the `small` scene rendered by `tlsmon simulate` 32 h 45 min apart (the next
// afternoon's bending, the pier's south face up to 7.5 mm nearer the scanner at its top),
// measured by `tlsmon m3c2 --config` with the site's south-face zone, drawn by the simulator
// from corner to corner and from the ground up. The pier's field does not vary along a face's
// width (report/truth.hpp), so every core point of one row of the face has the same true
// change and shares the registration's error within a fraction of a millimetre: each core
// point's error against the truth lies within 2 mm of its row's median error. As published
// (`--stray-distance 100`), the cylinders at the south-west corner and over the foundation
// at the foot take in the west face and the foundation's top, and err by 1–3 cm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "report/truth.hpp"
#include "tests/support/csv_cells.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/small_scene.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace fs = std::filesystem;

namespace {

using tlsmon::test::run_tlsmon;

struct CorePoint {
    Eigen::Vector3d place;
    double distance = 0, error = 0;
};

// The south face's core points with a distance (its zone's box, the simulator's site.toml),
// each with its error against the truth's change along the face's normal (0, −1, 0).
std::vector<CorePoint> south_face(const fs::path& csv,
                                  const std::vector<tlsmon::report::TruthEpoch>& truth) {
    const auto rows = tlsmon::test::csv_cells(tlsmon::test::read_text(csv));
    EXPECT_GT(rows.size(), 1u);
    if (rows.size() < 2) return {};
    std::map<std::string, std::size_t> column;
    for (std::size_t c = 0; c < rows[0].size(); ++c) column[rows[0][c]] = c;
    const Eigen::Vector3d normal(0, -1, 0);
    std::vector<CorePoint> out;
    for (std::size_t r = 1; r < rows.size(); ++r) {
        const auto& row = rows[r];
        if (row.empty() || row[column.at("distance_m")].empty()) continue;
        CorePoint p;
        p.place = {std::stod(row[column.at("x_m")]), std::stod(row[column.at("y_m")]),
                   std::stod(row[column.at("z_m")])};
        if (p.place.x() < 2 || p.place.x() > 17 || std::abs(p.place.y() - 45) > 0.5) continue;
        p.distance = std::stod(row[column.at("distance_m")]);
        const Eigen::Vector3d change = tlsmon::report::true_displacement(truth[1], p.place) -
                                       tlsmon::report::true_displacement(truth[0], p.place);
        p.error = p.distance - change.dot(normal);
        out.push_back(p);
    }
    return out;
}

// The largest |error − its row's median error| (rows of core points 0.5 m apart in height).
double worst_in_row(const std::vector<CorePoint>& points) {
    std::map<long, std::vector<double>> rows;
    for (const auto& p : points) rows[std::lround(2 * p.place.z())].push_back(p.error);
    double worst = 0;
    for (auto& [row, errors] : rows) {
        std::vector<double> sorted = errors;
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        const double median = sorted[sorted.size() / 2];
        for (const double e : errors) worst = std::max(worst, std::abs(e - median));
    }
    return worst;
}

}  // namespace

TEST(M3c2Edges, StraysAtTheCornerAndTheFootAreLeftOutOfTheirCylinders) {
    const tlsmon::test::TempDir dir("m3c2-edges");
    tlsmon::test::write_text(dir / "scene.toml", tlsmon::test::small_scene_text(31));
    const auto sim = run_tlsmon("simulate --config " + (dir / "scene.toml").string() + " --out " +
                                (dir / "scans").string() + " --epochs 2 --cadence 1965min");
    ASSERT_EQ(sim.status, 0) << sim.out;
    const auto truth = tlsmon::report::read_truth_folder(dir / "scans");
    ASSERT_EQ(truth.size(), 2u);
    // The site as the simulator wrote it; its 0.1° spheres give σ(ω) of 8–18″.
    tlsmon::test::write_text(dir / "site.toml",
                             tlsmon::test::read_text(dir / "scans" / "site.toml") +
                                 "\n[registration]\nmax_sigma_angle_arcsec = 20\n");
    std::vector<fs::path> scans;
    for (const auto& f : fs::directory_iterator(dir / "scans"))
        if (f.path().extension() == ".ptx") scans.push_back(f.path());
    std::sort(scans.begin(), scans.end());
    ASSERT_EQ(scans.size(), 2u);

    const auto measure = [&](const std::string& name, const std::string& options) {
        const fs::path csv = dir / (name + ".csv");
        const auto run =
            run_tlsmon("m3c2 --config " + (dir / "site.toml").string() + " " + scans[0].string() +
                       " " + scans[1].string() + " --out " + csv.string() + options);
        EXPECT_EQ(run.status, 0) << run.out;
        return south_face(csv, truth);
    };
    const auto kept = measure("strays_left_out", "");
    const auto published = measure("published", " --stray-distance 100");
    ASSERT_GT(kept.size(), 1000u);
    ASSERT_GT(published.size(), 1000u);

    // The face moved: the test measures something.
    double largest = 0;
    for (const auto& p : kept) largest = std::max(largest, std::abs(p.distance - p.error));
    EXPECT_GT(largest, 0.005);
    const double worst = worst_in_row(kept), worst_published = worst_in_row(published);
    std::printf(
        "largest true change %.2f mm; worst core point against its row: %.2f mm, "
        "as published %.2f mm\n",
        1e3 * largest, 1e3 * worst, 1e3 * worst_published);
    EXPECT_LT(worst, 0.002);
    EXPECT_GT(worst_published, 0.01);
}
