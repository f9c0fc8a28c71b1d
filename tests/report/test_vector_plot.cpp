// The report's figure of the 3-D vectors (report/vector_plot.cpp): for the newest registered
// epoch with vectors, each zone's measured areas (those whose centre lies in its box, with a
// σ) written in the wall frame — u along the wall, v up — and drawn; an area without a
// vector, or outside the box, is not. Against values set here, read back from the figure's
// data file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "pipeline/stored_area_vectors.hpp"
#include "report/gnuplot.hpp"
#include "report/output.hpp"
#include "tests/storage/fake_sha256.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::report {
namespace {

namespace fs = std::filesystem;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(VectorPlot, TheNewestEpochsAreasOfEachZoneInTheWallFrame) {
    if (!have_gnuplot()) GTEST_FAIL() << "gnuplot is part of the test dependencies";
    test::TempDir dir;
    {
        auto db = EpochDatabase::open(dir / "e.sqlite", EpochDatabase::Mode::read_write);
        // A wall along x at y = 45 (a south face: the box is thin along y).
        db.site().upsert_zone("south", R"({"type":"box","min":[0,44.5,0],"max":[10,45.5,20]})");
        for (int e = 0; e < 2; ++e) {
            const EpochId id =
                db.epochs()
                    .insert({test::fake_sha256(e + 1), 1'800'000'000 + 900 * e, "/i/s.ptx", 10, {}})
                    .id;
            ASSERT_TRUE(db.epochs().claim(id));
            if (e == 0) db.epochs().set_reference(id);
            EpochResults r;
            RegistrationRow g;
            g.method = "targets";
            g.accepted = true;
            g.parameters = std::array<double, 6>{};
            r.registration = g;
            if (e == 1) {
                // Areas: inside (two measured, one without a vector) and one outside the box.
                const std::vector<std::array<float, 9>> areas = {
                    {2.0f, 45.0f, 5.0f, 0.001f, -0.0002f, 0.0005f, 1e-4f, 1e-4f, 1e-4f},
                    {6.0f, 45.0f, 12.0f, -0.0001f, 0.0f, 0.002f, 5e-4f, 5e-4f, 5e-4f},
                    {4.0f, 45.0f, 8.0f, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN},
                    {30.0f, 45.0f, 8.0f, 0.003f, 0.0f, 0.0f, 1e-4f, 1e-4f, 1e-4f}};
                for (std::size_t c = 0; c < kAreaVectorArrays.size(); ++c) {
                    CorePointArray a{kAreaVectorArrays[c], {}};
                    for (const auto& area : areas) a.values.push_back(area[c]);
                    r.core_point_arrays.push_back(std::move(a));
                }
            }
            db.results().commit(id, r);
        }
    }
    const RunReport r = analyse(read_run(dir / "e.sqlite"), {}, "");
    const fs::path plots = dir / "out" / "plots";
    fs::create_directories(plots);
    ReportFiles files;
    draw_area_vectors(r, plots, files);
    ASSERT_EQ(files.plots.size(), 1u) << (files.notes.empty() ? "" : files.notes[0]);
    EXPECT_EQ(files.plots[0].filename(), "vectors_south.png");
    EXPECT_GT(fs::file_size(files.plots[0]), 1000u);
    // Without a truth the box's thin side, y, is the normal, so u = up × n = ±x and v = z;
    // the rows read back against the stored values, in mm.
    const auto rows = [&](const char* name) {
        std::ifstream f(plots / name);
        std::vector<std::array<double, 4>> out;
        std::string line;
        while (std::getline(f, line)) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream s(line);
            std::array<double, 4> v{};
            s >> v[0] >> v[1] >> v[2] >> v[3];
            out.push_back(v);
        }
        return out;
    };
    const auto beyond = rows("vectors_south_beyond.dat"), within = rows("vectors_south_within.dat");
    // The first: 1 mm along x at σ 0.1 mm, beyond; the second: 2 mm up at σ 0.5 mm (LoD95
    // 0.98 mm), beyond too; the NaN area and the one outside the box are not drawn.
    ASSERT_EQ(beyond.size(), 2u);
    EXPECT_TRUE(within.empty());
    const double sign = beyond[0][0] / 2.0;  // u = ±x
    ASSERT_NEAR(std::abs(sign), 1.0, 1e-9);
    EXPECT_NEAR(beyond[0][1], 5.0, 1e-4);
    EXPECT_NEAR(beyond[0][2], sign * 1.0, 1e-4);
    EXPECT_NEAR(beyond[0][3], 0.5, 1e-4);
    EXPECT_NEAR(beyond[1][0], sign * 6.0, 1e-4);
    EXPECT_NEAR(beyond[1][3], 2.0, 1e-4);
    EXPECT_TRUE(rows("vectors_south_truth.dat").empty()) << "no truth, no truth arrows";
}

}  // namespace
}  // namespace tlsmon::report
