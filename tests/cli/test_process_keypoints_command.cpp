// `tlsmon keypoints`: runs the built binary on the real "no change" pair of INVENTORY.md —
// the pump scan as PTX and as pye57's E57 (the same 155,201 points, equal within 1 µm) — and
// checks the CSV (every vector zero to a hundredth of a pixel), the pictures, and clear
// errors.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path data = TLSMON_DATA_DIR;
const std::string ptx = (data / "ptx/pumpA_from_e57.ptx").string();
const std::string e57 = (data / "e57/pye57/pumpAVisualReferenceImage.e57").string();
const std::string unstructured = (data / "xyz/plane_horizontal_t1.xyz").string();

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

class KeypointsCommand : public ::testing::Test {
  protected:
    int run(const std::vector<std::string>& args) {
        std::string cmd = quoted(TLSMON_BINARY) + " keypoints";
        for (const auto& a : args) cmd.append(" ").append(quoted(a));
        cmd +=
            " >" + quoted((dir_ / "stdout").string()) + " 2>" + quoted((dir_ / "stderr").string());
        const int status = std::system(cmd.c_str());
        out_ = tlsmon::test::read_file(dir_ / "stdout");
        err_ = tlsmon::test::read_file(dir_ / "stderr");
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    tlsmon::test::TempDir dir_;
    std::string out_, err_;
};

TEST_F(KeypointsCommand, NoChangePairGivesZeroVectors) {
    const fs::path csv = dir_ / "vectors.csv";
    const fs::path pictures = dir_ / "pictures";
    ASSERT_EQ(run({ptx, e57, "--window-deg", "0.3", "--detector", "kaze", "--out", csv.string(),
                   "--images", pictures.string()}),
              0)
        << err_;
    std::istringstream in(tlsmon::test::read_file(csv));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line,
              "reference_row_px,reference_column_px,row_px,column_px,x_m,y_m,z_m,dx_m,dy_m,dz_m,"
              "descriptor_distance,segment,zone,removed_by");
    std::size_t rows = 0, kept = 0;
    double sum[3] = {0, 0, 0};
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::istringstream fields(line);
        std::string s;
        while (std::getline(fields, s, ',')) f.push_back(s);
        if (line.back() == ',') f.push_back("");
        ASSERT_EQ(f.size(), 14u) << line;
        // Same scan (its values rounded differently in the two files): each keypoint is
        // found at its own place to a few hundredths of a pixel (0.05), so the vector is
        // below 0.05 of a column step (0.25°) at ≤ 5.43 m, 1.2 mm; and the range lies in the
        // file's 1.98–5.43 m.
        EXPECT_NEAR(std::stod(f[0]), std::stod(f[2]), 0.05) << line;
        EXPECT_NEAR(std::stod(f[1]), std::stod(f[3]), 0.05) << line;
        const double r = std::hypot(std::stod(f[4]), std::stod(f[5]), std::stod(f[6]));
        EXPECT_GT(r, 1.97);
        EXPECT_LT(r, 5.44);
        for (int k = 7; k <= 9; ++k) {
            EXPECT_LE(std::abs(std::stod(f[k])), 1.2e-3) << line;
            sum[k - 7] += std::stod(f[k]);
        }
        // Segment: the 5° band of the vertical angle (−45°…28° in this scan: bands 9…23).
        const int segment = std::stoi(f[11]);
        EXPECT_EQ(segment, static_cast<int>(
                               std::floor((std::asin(std::stod(f[6]) / r) * 180 / M_PI + 90) / 5)));
        EXPECT_EQ(f[12].rfind("keypoint_band_", 0), 0u) << line;
        // Empty (kept) or the name of the outlier filter that removed it.
        static const std::set<std::string> names = {"",
                                                    "row_difference",
                                                    "column_difference",
                                                    "range_difference",
                                                    "horizontal_angle_difference",
                                                    "vertical_angle_difference",
                                                    "dx",
                                                    "dy",
                                                    "dz",
                                                    "magnitude",
                                                    "angle_to_median"};
        EXPECT_TRUE(names.count(f[13])) << line;
        kept += f[13].empty();
        ++rows;
    }
    EXPECT_GT(rows, 200u);
    EXPECT_GT(kept, 0u);
    // And on average no movement, to 0.1 mm.
    for (double v : sum) EXPECT_LE(std::abs(v / static_cast<double>(rows)), 1e-4);
    // The parameters used: a fresh site's with bands, the detector replaced; the summary per
    // band.
    EXPECT_NE(out_.find("keypoints.detector = \"kaze\""), std::string::npos) << out_;
    EXPECT_NE(out_.find("keypoints.window_deg = 0.3"), std::string::npos) << out_;
    EXPECT_NE(out_.find("keypoints.refine = true"), std::string::npos) << out_;
    EXPECT_NE(out_.find("keypoints.segments = \"bands\""), std::string::npos) << out_;
    EXPECT_NE(out_.find("\nkeypoint_band_"), std::string::npos) << out_;
    for (const char* name : {"reference.png", "epoch.png"}) {
        const std::string png = tlsmon::test::read_file(pictures / name);
        ASSERT_GT(png.size(), 1000u) << name;
        EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
    }
}

TEST_F(KeypointsCommand, ClearErrors) {
    const std::string csv = (dir_ / "v.csv").string();
    EXPECT_EQ(run({unstructured, ptx, "--out", csv}), 1);
    EXPECT_NE(err_.find("plane_horizontal_t1.xyz"), std::string::npos) << err_;
    EXPECT_NE(err_.find("no structured scan"), std::string::npos) << err_;
    EXPECT_EQ(run({ptx, ptx, "--detector", "surf", "--out", csv}), 1);
    EXPECT_NE(err_.find("unknown detector 'surf'"), std::string::npos) << err_;
    EXPECT_EQ(run({ptx, (dir_ / "missing.ptx").string(), "--out", csv}), 1);
    EXPECT_NE(err_.find("missing.ptx"), std::string::npos) << err_;
}

}  // namespace
