// PLY and PCD through PCL: files written here byte by byte (not with PCL) with known points,
// read back through read_scans; broken copies rejected with the file named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "formats/format_error.hpp"
#include "formats/pcl_formats.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

class PclFormats : public ::testing::Test {
  protected:
    fs::path write(const std::string& name, const std::string& bytes) const {
        return test::write_file(dir_ / name, bytes);
    }

    test::TempDir dir_;
};

template <class T>
void append(std::string& out, T v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    out.append(b, sizeof v);
}

std::string error_of(const fs::path& p) {
    try {
        read_scans(p);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

// Three known points: a survey-sized coordinate that float32 could not hold, colour, intensity.
struct Point {
    double x, y, z;
    float intensity;
    std::uint8_t r, g, b;
};
const std::vector<Point> kPoints = {{637012.24, 849028.31, 431.66, 0.25f, 255, 0, 10},
                                    {-1.5, 2.25, -3.125, 0.5f, 1, 2, 3},
                                    {0.001, 0.002, 0.003, 1.0f, 68, 77, 88}};

void expect_known_points(const Scan& scan, double tolerance) {
    ASSERT_EQ(scan.size(), kPoints.size());
    ASSERT_EQ(scan.intensity.size(), kPoints.size());
    ASSERT_EQ(scan.rgb.size(), kPoints.size());
    for (std::size_t i = 0; i < kPoints.size(); ++i) {
        EXPECT_NEAR(scan.xyz[i].x(), kPoints[i].x, tolerance) << i;
        EXPECT_NEAR(scan.xyz[i].y(), kPoints[i].y, tolerance) << i;
        EXPECT_NEAR(scan.xyz[i].z(), kPoints[i].z, tolerance) << i;
        EXPECT_EQ(scan.rgb[i], (Rgb8{kPoints[i].r, kPoints[i].g, kPoints[i].b})) << i;
        // Intensity already in 0..1: the raw scale stays 0..1.
        EXPECT_FLOAT_EQ(scan.intensity[i], kPoints[i].intensity) << i;
    }
    EXPECT_EQ(scan.intensity_raw_min, 0.0);
    EXPECT_EQ(scan.intensity_raw_max, 1.0);
}

std::string ply_header(const std::string& format, std::size_t n) {
    return "ply\nformat " + format + " 1.0\ncomment written by tlsmon tests\nelement vertex " +
           std::to_string(n) +
           "\nproperty double x\nproperty double y\nproperty double z\n"
           "property float intensity\nproperty uchar red\nproperty uchar green\n"
           "property uchar blue\nend_header\n";
}

std::string ply_ascii() {
    std::string s = ply_header("ascii", kPoints.size());
    for (const auto& p : kPoints) {
        char line[200];
        std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.9g %d %d %d\n", p.x, p.y, p.z,
                      p.intensity, p.r, p.g, p.b);
        s += line;
    }
    return s;
}

std::string ply_binary() {
    std::string s = ply_header("binary_little_endian", kPoints.size());
    for (const auto& p : kPoints) {
        append(s, p.x), append(s, p.y), append(s, p.z), append(s, p.intensity);
        append(s, p.r), append(s, p.g), append(s, p.b);
    }
    return s;
}

std::uint32_t packed(const Point& p) {  // PCL's 0x00RRGGBB
    return std::uint32_t{p.r} << 16 | std::uint32_t{p.g} << 8 | p.b;
}

std::string pcd_header(const std::string& data, std::size_t width, std::size_t height) {
    return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
           "FIELDS x y z intensity rgb\nSIZE 8 8 8 4 4\nTYPE F F F F U\nCOUNT 1 1 1 1 1\n"
           "WIDTH " +
           std::to_string(width) + "\nHEIGHT " + std::to_string(height) +
           "\nVIEWPOINT 10 20 30 1 0 0 0\nPOINTS " + std::to_string(width * height) + "\nDATA " +
           data + "\n";
}

std::string pcd_ascii() {
    std::string s = pcd_header("ascii", kPoints.size(), 1);
    for (const auto& p : kPoints) {
        char line[200];
        std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.9g %u\n", p.x, p.y, p.z, p.intensity,
                      packed(p));
        s += line;
    }
    return s;
}

std::string pcd_binary_records(const std::vector<Point>& points) {
    std::string s;
    for (const auto& p : points) {
        append(s, p.x), append(s, p.y), append(s, p.z), append(s, p.intensity);
        append(s, packed(p));
    }
    return s;
}

TEST_F(PclFormats, PlyAsciiRoundTrip) {
    const fs::path p = write("cloud.ply", ply_ascii());
    EXPECT_EQ(detect_format(p), ScanFormat::ply);
    const auto scans = read_scans(p);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].source, p.string());
    expect_known_points(scans[0], 1e-9);
}

TEST_F(PclFormats, PlyBinaryRoundTrip) {
    expect_known_points(read_scans(write("cloud.ply", ply_binary())).at(0), 0.0);
}

TEST_F(PclFormats, PcdAsciiRoundTripWithViewpoint) {
    const Scan scan = read_scans(write("cloud.pcd", pcd_ascii())).at(0);
    expect_known_points(scan, 1e-9);
    EXPECT_EQ(scan.scanner_position(), Eigen::Vector3d(10, 20, 30));
    EXPECT_FALSE(scan.grid.has_value());
}

TEST_F(PclFormats, PcdBinaryRoundTrip) {
    const std::string bytes = pcd_header("binary", kPoints.size(), 1) + pcd_binary_records(kPoints);
    expect_known_points(read_scans(write("cloud.pcd", bytes)).at(0), 0.0);
}

TEST_F(PclFormats, OrganisedPcdKeepsItsGridAndSkipsNaNCells) {
    std::vector<Point> cells = kPoints;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    cells.insert(cells.begin() + 1, Point{nan, nan, nan, 0.0f, 0, 0, 0});  // no return
    const std::string bytes = pcd_header("binary", 2, 2) + pcd_binary_records(cells);
    const Scan scan = read_scans(write("organised.pcd", bytes)).at(0);
    expect_known_points(scan, 0.0);
    ASSERT_TRUE(scan.grid.has_value());
    EXPECT_EQ(scan.grid->rows, 2u);
    EXPECT_EQ(scan.grid->columns, 2u);
    // Cells in row-major order: (0,0) point 0, (0,1) empty, (1,0) point 1, (1,1) point 2.
    EXPECT_EQ(scan.grid->row, (std::vector<std::uint32_t>{0, 1, 1}));
    EXPECT_EQ(scan.grid->column, (std::vector<std::uint32_t>{0, 0, 1}));
}

TEST_F(PclFormats, IntensityRawScaleFollowsTheFieldType) {
    // uint8 intensity: raw 0..255.
    const std::string u8 =
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 1\nTYPE F F F U\n"
        "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 51\n4 5 6 255\n";
    const Scan a = read_scans(write("u8.pcd", u8)).at(0);
    EXPECT_EQ(a.intensity_raw_max, 255.0);
    EXPECT_FLOAT_EQ(a.intensity[0], 0.2f);
    EXPECT_FLOAT_EQ(a.intensity[1], 1.0f);
    // float intensity outside 0..1: the data's own range, here 100..1100.
    const std::string f =
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
        "COUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n1 2 3 100\n4 5 6 1100\n"
        "7 8 9 350\n";
    const Scan b = read_scans(write("f.pcd", f)).at(0);
    EXPECT_EQ(b.intensity_raw_min, 100.0);
    EXPECT_EQ(b.intensity_raw_max, 1100.0);
    EXPECT_FLOAT_EQ(b.intensity[2], 0.25f);
    EXPECT_TRUE(b.rgb.empty());
}

TEST_F(PclFormats, BrokenFilesAreFormatErrorsNamingTheFile) {
    std::vector<fs::path> broken;
    const std::string binary_ply = ply_binary();
    broken.push_back(write("truncated_binary.ply", binary_ply.substr(0, binary_ply.size() - 9)));
    const std::string ascii_ply = ply_ascii();
    broken.push_back(write("truncated_ascii.ply", ascii_ply.substr(0, ascii_ply.size() - 30)));
    broken.push_back(write("bad_header.ply", "ply\nformat unknown 1.0\nend_header\n1 2 3\n"));
    broken.push_back(write("header_only.ply", "ply\nformat ascii 1.0\nelement vertex 5\n"));
    broken.push_back(write("no_xyz.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\n"
                           "end_header\n1\n"));
    const std::string binary_pcd =
        pcd_header("binary", kPoints.size(), 1) + pcd_binary_records(kPoints);
    broken.push_back(write("truncated_binary.pcd", binary_pcd.substr(0, binary_pcd.size() - 9)));
    const std::string ascii_pcd = pcd_ascii();
    broken.push_back(write("truncated_ascii.pcd", ascii_pcd.substr(0, ascii_pcd.size() - 30)));
    broken.push_back(
        write("garbage.pcd", std::string("# .PCD v0.7\nVERSION 0.7\n\x01\x02\xff", 27)));
    broken.push_back(write("empty.pcd", ""));
    broken.push_back(write("no_xyz.pcd",
                           "VERSION 0.7\nFIELDS a\nSIZE 4\nTYPE F\nCOUNT 1\nWIDTH 1\nHEIGHT 1\n"
                           "POINTS 1\nDATA ascii\n1\n"));
    broken.push_back(dir_ / "missing.pcd");
    // ASCII PCD lines PCL would skip or read as 0 are errors naming the line.
    const std::string header = pcd_header("ascii", 3, 1);  // 11 lines
    const fs::path short_line =
        write("short_line.pcd", header + "1 2 3 0.5 7\n1 2 3\n1 2 3 0.5 7\n");
    EXPECT_NE(error_of(short_line).find("short_line.pcd:13: 3 values, the header declares 5"),
              std::string::npos)
        << error_of(short_line);
    const fs::path word = write("word.pcd", header + "1 2 3 0.5 7\n1 2 abc 0.5 7\n1 2 3 0.5 7\n");
    EXPECT_NE(error_of(word).find("word.pcd:13: \"abc\" is not a number"), std::string::npos)
        << error_of(word);
    const fs::path few = write("few.pcd", header + "1 2 3 0.5 7\n\n");
    EXPECT_NE(error_of(few).find("few.pcd:14: file ends after 1 points, the header declares 3"),
              std::string::npos)
        << error_of(few);
    for (const auto& p : broken) {
        const std::string m = error_of(p);
        EXPECT_EQ(m.rfind(p.string() + ":", 0), 0u) << p << " -> \"" << m << "\"";
    }
}

}  // namespace
}  // namespace tlsmon
