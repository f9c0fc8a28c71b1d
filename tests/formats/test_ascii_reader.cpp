// PTS / XYZ reader on the real files of ../shared/data/xyz (expected values from its
// INVENTORY.md) and on small and broken files made in a temporary folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>

#include "formats/ascii_reader.hpp"
#include "formats/format_error.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/rejected_files.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;
using tlsmon::FormatError;
using tlsmon::read_pts;
using tlsmon::read_xyz;
using tlsmon::Scan;

namespace {

const fs::path data = fs::path(TLSMON_DATA_DIR) / "xyz";

double mean_z(const Scan& s) {
    double sum = 0;
    for (const auto& p : s.xyz) sum += p.z();
    return sum / static_cast<double>(s.size());
}

class AsciiFiles : public tlsmon::test::RejectedFiles {};

}  // namespace

TEST(XyzReader, PlanesHave441PointsAndTheirMeanHeights) {
    const auto t1 = tlsmon::read_scans(data / "plane_horizontal_t1.xyz");
    const auto t2 = read_xyz(data / "plane_horizontal_t2.xyz");
    ASSERT_EQ(t1.size(), 1u);
    ASSERT_EQ(t2.size(), 1u);
    EXPECT_EQ(t1[0].size(), 441u);
    EXPECT_EQ(t2[0].size(), 441u);
    EXPECT_NEAR(mean_z(t1[0]), 3.5002, 0.00005);
    EXPECT_NEAR(mean_z(t2[0]), 3.4000, 0.00005);
    EXPECT_EQ(t1[0].xyz[0], Eigen::Vector3d(-10.0, -10.0, 3.5048730360909897));
    EXPECT_TRUE(t1[0].intensity.empty());
    EXPECT_TRUE(t1[0].rgb.empty());
    EXPECT_FALSE(t1[0].grid);
}

TEST_F(AsciiFiles, PtsCountIntensityAndColour) {
    const auto scans = read_pts(write("a.pts",
                                      "3\n"
                                      "1.5 2.5 3.5 -2048 10 20 30\n"
                                      "4,5,6,2047,40,50,60\n"
                                      "7\t8\t9\t0\t70\t80\t90\n"));
    ASSERT_EQ(scans.size(), 1u);
    const Scan& s = scans[0];
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s.xyz[1], Eigen::Vector3d(4, 5, 6));
    EXPECT_EQ(s.intensity_raw_min, -2048.0);
    EXPECT_EQ(s.intensity_raw_max, 2047.0);
    EXPECT_FLOAT_EQ(s.intensity[0], 0.0f);
    EXPECT_FLOAT_EQ(s.intensity[1], 1.0f);
    EXPECT_NEAR(s.intensity[2], 2048.0 / 4095.0, 1e-6);
    EXPECT_EQ(s.rgb[2], (tlsmon::Rgb8{70, 80, 90}));
}

TEST_F(AsciiFiles, PtsWithSeveralBlocksGivesSeveralScans) {
    const fs::path p = write("two.pts", "2\n1 2 3 0\n4 5 6 0\n1\n7 8 9 100\n");
    const auto scans = read_pts(p);
    ASSERT_EQ(scans.size(), 2u);
    EXPECT_EQ(scans[0].size(), 2u);
    EXPECT_EQ(scans[1].xyz[0], Eigen::Vector3d(7, 8, 9));
    EXPECT_EQ(scans[1].source, p.string() + "#2");
}

TEST_F(AsciiFiles, XyzCommentsColourAndIntensityScales) {
    const auto rgb = read_xyz(write("rgb.xyz",
                                    "# exported by a scanner\n// x y z r g b\n"
                                    "1 2 3 255 0 7\n\n +4 5 6 1 2 3\r\n"));
    ASSERT_EQ(rgb[0].size(), 2u);
    EXPECT_TRUE(rgb[0].intensity.empty());
    EXPECT_EQ(rgb[0].rgb[0], (tlsmon::Rgb8{255, 0, 7}));
    EXPECT_EQ(rgb[0].xyz[1], Eigen::Vector3d(4, 5, 6));

    const auto unit = read_xyz(write("unit.xyz", "1 2 3 0.25\n4 5 6 0.75\n"));
    EXPECT_EQ(unit[0].intensity_raw_max, 1.0);
    EXPECT_FLOAT_EQ(unit[0].intensity[0], 0.25f);

    const auto byte = read_xyz(write("byte.xyz", "1 2 3 51\n4 5 6 2\n"));
    EXPECT_EQ(byte[0].intensity_raw_max, 255.0);
    EXPECT_FLOAT_EQ(byte[0].intensity[0], 0.2f);

    const auto word = read_xyz(write("word.xyz", "1 2 3 65535 1 1 1\n4 5 6 300 1 1 1\n"));
    EXPECT_EQ(word[0].intensity_raw_max, 65535.0);
    EXPECT_FLOAT_EQ(word[0].intensity[0], 1.0f);
    EXPECT_EQ(word[0].rgb.size(), 2u);

    const auto own = read_xyz(write("own.xyz", "1 2 3 -10\n4 5 6 30\n"));
    EXPECT_EQ(own[0].intensity_raw_min, -10.0);
    EXPECT_EQ(own[0].intensity_raw_max, 30.0);
    EXPECT_FLOAT_EQ(own[0].intensity[1], 1.0f);
}

TEST_F(AsciiFiles, BrokenFilesAreRejectedAtTheirLine) {
    expect_rejected(write("short.pts", "3\n1.5 2.5 3.5 0\n4.5 5.5 6.5 0\n"), 3,
                    "declares 3 points");
    expect_rejected(write("long.pts", "1\n1 2 3 0\n4 5 6 0\n"), 3, "more point lines");
    expect_rejected(write("huge.pts", "900000000000\n1 2 3 0\n"), 1, "bytes follow");
    expect_rejected(write("intensity.pts", "1 2 3 5000\n"), 1, "-2048..2047");
    expect_rejected(write("nan.xyz", "1 2 3\n4 nan 6\n"), 2, "non-finite");
    expect_rejected(write("inf.xyz", "1 2 3\n4 5 inf\n"), 2, "non-finite");
    expect_rejected(write("word.xyz", "1 2 3\n4 five 6\n"), 2, "not a number");
    expect_rejected(write("five.xyz", "1 2 3 4 5\n"), 1, "3, 4, 6 or 7 values");
    expect_rejected(write("count.xyz", "12\n1 2 3\n"), 1, "3, 4, 6 or 7 values");
    expect_rejected(write("mixed.xyz", "1 2 3\n1 2 3 4\n"), 2, "earlier lines");
    expect_rejected(write("eight.xyz", "1 2 3 4 5 6 7 8\n"), 1, "more than 7");
    expect_rejected(write("colour.xyz", "1 2 3 0 0 -1\n"), 1, "colour");
    expect_rejected(write("binary.xyz", std::string("1 2 3\n\x7f\x45\x4c\x46\x02\x01", 12)), 2,
                    "not a number");
    // A decimal comma reads as six values without this check.
    expect_rejected(write("comma.xyz", "1,5 2,25 3,75\n4,5 5,5 6,5\n"), 1, "decimal comma");
    expect_rejected(write("comma.pts", "1\n1,5 2,25 3,75 10\n"), 2, "'1,5' is written");
    // Cut inside its last line, which still holds three values.
    expect_rejected(write("cut.xyz", "1.25 2.5 3.75\n4.25 5.5 6"), 2, "cut short");
    EXPECT_EQ(read_xyz(write("csv.xyz", "1.5,2.5,3.5\n4.5, 5.5, 6.5\n"))[0].xyz[1],
              Eigen::Vector3d(4.5, 5.5, 6.5));
    EXPECT_EQ(read_xyz(write("one.xyz", "1.5 2.5 3.5"))[0].size(), 1u);
    EXPECT_THROW(read_xyz(write("empty.xyz", "")), FormatError);
    EXPECT_THROW(read_xyz(write("comments.xyz", "# nothing\n")), FormatError);
    EXPECT_THROW(read_pts(write("zero.pts", "0\n")), FormatError);
}

TEST_F(AsciiFiles, EveryTruncationOfARealFileIsReadOrRejected) {
    const std::string full = tlsmon::test::read_file(data / "plane_horizontal_t1.xyz");
    std::mt19937 rng(3);
    for (int k = 0; k < 200; ++k) {
        const std::size_t n = rng() % full.size();
        const fs::path p = write("cut.xyz", full.substr(0, n));
        const auto lines = std::count(full.begin(), full.begin() + n, '\n');
        // Cut at the end of a line: read, every whole line. Cut inside a line after the
        // first: rejected, even where the cut line still holds three values ("1 2 3" of
        // "1 2 3.504"), naming the cut.
        const bool at_line_end = n == 0 || full[n - 1] == '\n';
        if (at_line_end && n > 0) {
            EXPECT_EQ(read_xyz(p)[0].size(), static_cast<std::size_t>(lines));
        } else if (lines > 0) {
            try {
                read_xyz(p);
                ADD_FAILURE() << "a file cut inside line " << lines + 1 << " was read";
            } catch (const FormatError& e) {
                EXPECT_EQ(std::string(e.what()).rfind(p.string() + ":", 0), 0u) << e.what();
            }
        }
    }
}
