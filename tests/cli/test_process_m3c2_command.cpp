// `tlsmon m3c2`: runs the built binary on the real pair of ../shared/data/xyz (t2 is t1
// lowered by 0.100 m, INVENTORY.md) and checks the CSV it writes: one row per core point,
// distances of -0.100 m along the upward normal, and clear errors for bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path data = TLSMON_DATA_DIR;
const std::string t1 = (data / "xyz/plane_horizontal_t1.xyz").string();
const std::string t2 = (data / "xyz/plane_horizontal_t2.xyz").string();

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

struct Row {
    std::vector<double> v;  // the 14 columns; an empty field (no value) read as NaN
    double operator[](std::size_t i) const { return v.at(i); }
};
enum Column {
    x,
    y,
    z,
    nx,
    ny,
    nz,
    normal_radius,
    distance,
    lod,
    spread1,
    n1,
    spread2,
    n2,
    significant
};

class M3c2Command : public ::testing::Test {
  protected:
    int run(const std::vector<std::string>& args) {
        std::string cmd = quoted(TLSMON_BINARY) + " m3c2";
        for (const auto& a : args) cmd.append(" ").append(quoted(a));
        cmd +=
            " >" + quoted((dir_ / "stdout").string()) + " 2>" + quoted((dir_ / "stderr").string());
        const int status = std::system(cmd.c_str());
        out_ = tlsmon::test::read_file(dir_ / "stdout");
        err_ = tlsmon::test::read_file(dir_ / "stderr");
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::vector<Row> rows(const fs::path& csv) {
        std::istringstream in(tlsmon::test::read_file(csv));
        std::string line;
        std::getline(in, line);
        EXPECT_EQ(line,
                  "x_m,y_m,z_m,nx,ny,nz,normal_radius_m,distance_m,lod95_m,spread1_m,n1,spread2_m,"
                  "n2,significant");
        std::vector<Row> out;
        while (std::getline(in, line)) {
            Row r;
            std::istringstream fields(line);
            std::string f;
            while (std::getline(fields, f, ','))
                r.v.push_back(f.empty() ? std::nan("") : std::stod(f));
            EXPECT_EQ(r.v.size(), 14u) << line;
            out.push_back(r);
        }
        return out;
    }
    std::vector<std::string> pair_args(const fs::path& csv) {
        // The method as published: no roughness limit, no strays left out, 5 points a cylinder
        // (a site's defaults are 0.02 m, 0.01 m and 10).
        return {t1,
                t2,
                "--normal-radii",
                "2.0",
                "--cylinder-radius",
                "3.0",
                "--max-depth",
                "1.0",
                "--orient",
                "0,0,1",
                "--out",
                csv.string(),
                "--max-roughness",
                "100",
                "--min-points",
                "5",
                "--stray-distance",
                "100"};
    }

    tlsmon::test::TempDir dir_;
    std::string out_, err_;
};

TEST_F(M3c2Command, RealPairLoweredByTenCentimetres) {
    const fs::path csv = dir_ / "result.csv";
    ASSERT_EQ(run(pair_args(csv)), 0) << err_;
    const auto r = rows(csv);
    ASSERT_EQ(r.size(), 441u);  // every point of t1 is a core point
    double sum = 0;
    for (const auto& row : r) {
        EXPECT_GT(row[nz], 0.99);
        EXPECT_NEAR(std::hypot(row[nx], row[ny], row[nz]), 1.0, 1e-8);
        EXPECT_EQ(row[normal_radius], 2.0);
        EXPECT_GE(row[n1], 5);
        EXPECT_GE(row[n2], 5);
        // LoD95 = 1.96 sqrt(s1^2/n1 + s2^2/n2) with reg 0 (CSV rounding: 1e-8).
        EXPECT_NEAR(row[lod],
                    1.96 * std::sqrt(row[spread1] * row[spread1] / row[n1] +
                                     row[spread2] * row[spread2] / row[n2]),
                    1e-8);
        EXPECT_EQ(row[significant], 1.0);
        sum += row[distance];
    }
    EXPECT_NEAR(sum / r.size(), -0.100, 0.0005);
    EXPECT_NE(out_.find("441 core points, 441 with a distance"), std::string::npos) << out_;
}

TEST_F(M3c2Command, CoreSpacingMedianAndOrientation) {
    const fs::path csv = dir_ / "result.csv";
    auto args = pair_args(csv);
    args.insert(args.end(), {"--core-spacing", "5", "--median", "--reg-error", "0.01"});
    args[9] = "0,0,-1";  // normals down: the lowering is now positive
    ASSERT_EQ(run(args), 0) << err_;
    const auto r = rows(csv);
    // 21 x 21 points 1 m apart in x, y from -10 to 10, one height layer of 5 m cubes:
    // cubes -10..-5, -5..0, 0..5, 5..10 plus the line at 10: 5 per axis, 25 candidates. Each
    // full cube's is one of the 4 points around its centre (the heights decide); 4 of the
    // line's lie within 2.5 m (S/2) of a neighbour's candidate at 8 (or 3, 7 across a corner)
    // and are thinned.
    EXPECT_EQ(r.size(), 21u);
    for (const auto& row : r) {
        EXPECT_LT(row[nz], -0.99);
        EXPECT_NEAR(row[distance], 0.100, 0.005);
        EXPECT_GE(row[lod], 1.96 * 0.01);
    }
}

TEST_F(M3c2Command, OrientTowardsTheScanner) {
    // XYZ files carry no pose: the scanner is at the origin, below the planes (z = 3.5), so
    // normals point down and the lowering (towards the scanner) is positive.
    const fs::path csv = dir_ / "result.csv";
    auto args = pair_args(csv);
    args[9] = "scanner";
    ASSERT_EQ(run(args), 0) << err_;
    const auto r = rows(csv);
    ASSERT_EQ(r.size(), 441u);
    double sum = 0;
    for (const auto& row : r) {
        EXPECT_LT(row[nz], -0.99);
        sum += row[distance];
    }
    EXPECT_NEAR(sum / r.size(), 0.100, 0.0005);
}

TEST_F(M3c2Command, SparseCylindersAreNanInTheCsv) {
    const fs::path csv = dir_ / "result.csv";
    auto args = pair_args(csv);
    args[15] = "30";  // --min-points: at most 29 points within 3 m on 1 m
    ASSERT_EQ(run(args), 0) << err_;
    for (const auto& row : rows(csv)) {
        EXPECT_TRUE(std::isnan(row[distance]));
        EXPECT_TRUE(std::isnan(row[lod]));
        EXPECT_EQ(row[significant], 0.0);
    }
    EXPECT_NE(out_.find("441 core points, 0 with a distance"), std::string::npos) << out_;
}

TEST_F(M3c2Command, BadInputIsNamed) {
    const fs::path csv = dir_ / "result.csv";
    auto args = pair_args(csv);
    args[9] = "0,1";
    EXPECT_EQ(run(args), 1);
    EXPECT_NE(err_.find("--orient"), std::string::npos) << err_;
    args = pair_args(csv);
    args[3] = "0.5,-1";
    EXPECT_EQ(run(args), 1);
    EXPECT_NE(err_.find("normal_radii"), std::string::npos) << err_;
    args = pair_args(csv);
    args[1] = (dir_ / "missing.xyz").string();
    EXPECT_EQ(run(args), 1);
    EXPECT_NE(err_.find("missing.xyz"), std::string::npos) << err_;
    EXPECT_FALSE(fs::exists(csv));
}

}  // namespace
