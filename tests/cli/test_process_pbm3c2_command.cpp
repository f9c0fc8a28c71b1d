// `tlsmon pbm3c2`: runs the built binary on the real pair of ../shared/data/xyz (t2 is t1
// lowered by 0.100 m and shifted ≈ 7 mm in x and y, σ ≈ 3 mm, one point per square metre;
// INVENTORY.md) and checks the CSV it writes: every measured patch 0.100 m towards the
// scanner's side within its own σ, the LoD95 of its parts, and clear errors for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path data = TLSMON_DATA_DIR;
const std::string t1 = (data / "xyz/plane_horizontal_t1.xyz").string();
const std::string t2 = (data / "xyz/plane_horizontal_t2.xyz").string();

using Row = std::map<std::string, std::string>;

class PbM3c2Command : public ::testing::Test {
  protected:
    // Exit status; what it printed (standard output and error) in out_.
    int run(const std::vector<std::string>& args) {
        std::string line = "pbm3c2";
        for (const auto& a : args) line += " " + a;
        const auto r = tlsmon::test::run_tlsmon(line);
        out_ = r.out;
        return r.status;
    }
    std::vector<Row> rows(const fs::path& csv) {
        std::istringstream in(tlsmon::test::read_file(csv));
        std::string line;
        std::getline(in, line);
        std::vector<std::string> header;
        std::istringstream names(line);
        for (std::string f; std::getline(names, f, ',');) header.push_back(f);
        EXPECT_EQ(header.size(), 20u) << line;
        std::vector<Row> out;
        while (std::getline(in, line)) {
            std::istringstream fields(line);
            Row r;
            std::size_t i = 0;
            for (std::string f; std::getline(fields, f, ',') && i < header.size(); ++i)
                r[header[i]] = f;
            out.push_back(r);
        }
        return out;
    }
    // One point per square metre: voxels of 1 m, patches of 6 m, a depth beyond the 0.1 m.
    std::vector<std::string> pair_args(const fs::path& csv) {
        return {
            t1,   t2,      "--voxel",   "1", "--seed", "6", "--search-depth", "0.3", "--min-points",
            "20", "--out", csv.string()};
    }

    tlsmon::test::TempDir dir_;
    std::string out_;
};

double number(const Row& r, const char* column) {
    return std::stod(r.at(column));
}

TEST_F(PbM3c2Command, RealPairLoweredByTenCentimetres) {
    const fs::path csv = dir_ / "result.csv";
    ASSERT_EQ(run(pair_args(csv)), 0) << out_;
    const auto r = rows(csv);
    ASSERT_GE(r.size(), 10u);
    int measured = 0;
    for (const auto& row : r) {
        EXPECT_EQ(row.at("zones"), "all");
        if (row.at("outcome") != "measured") {
            EXPECT_TRUE(row.at("distance_m").empty());
            continue;
        }
        ++measured;
        // The file has no scanner position (the origin, below the plane): the normal points
        // down, and the lowered plane came 0.100 m closer to it.
        EXPECT_LT(number(row, "nz"), -0.99);
        const double sigma = number(row, "sigma_m");
        EXPECT_NEAR(number(row, "distance_m"), 0.100, 4 * sigma);
        EXPECT_NEAR(number(row, "lod95_m"), 1.96 * sigma, 1e-9);
        EXPECT_EQ(number(row, "registration_sigma_m"), 0.0);  // no registration
        // σ_d is at least the two centroids' σ, σ_i/√n_i (the slopes add to the epoch's).
        const double s1 = number(row, "sigma1_m") / std::sqrt(number(row, "n1"));
        const double s2 = number(row, "sigma2_m") / std::sqrt(number(row, "n2"));
        EXPECT_GE(sigma, std::hypot(s1, s2) - 1e-12);
        EXPECT_LT(sigma, 2 * std::hypot(s1, s2));
        // σ ≈ 3 mm per point (INVENTORY.md).
        EXPECT_NEAR(number(row, "sigma1_m"), 0.003, 0.0015);
        EXPECT_EQ(row.at("significant"), "1");
    }
    EXPECT_GE(measured, 10);
    EXPECT_NE(out_.find("all pbm3c2_median_m = 0.10"), std::string::npos) << out_;
    EXPECT_NE(out_.find("pbm3c2.search_depth = 0.3"), std::string::npos) << out_;
}

TEST_F(PbM3c2Command, BadInputIsNamed) {
    const fs::path csv = dir_ / "result.csv";
    auto args = pair_args(csv);
    args[5] = "0.5";  // --seed below --voxel
    EXPECT_EQ(run(args), 1);
    EXPECT_NE(out_.find("--seed"), std::string::npos) << out_;
    args = pair_args(csv);
    args[9] = "2";  // --min-points
    EXPECT_EQ(run(args), 1);
    EXPECT_NE(out_.find("min_points"), std::string::npos) << out_;
    args = pair_args(csv);
    args[1] = (dir_ / "missing.xyz").string();
    EXPECT_EQ(run(args), 1);
    EXPECT_NE(out_.find("missing.xyz"), std::string::npos) << out_;
    EXPECT_FALSE(fs::exists(csv));
}

}  // namespace
