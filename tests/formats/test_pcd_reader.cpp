// PCD: files written here byte by byte with known points (ascii, binary, binary_compressed
// with an LZF stream built here, organised clouds), read back through read_scans; broken
// copies rejected with the file and the place named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "formats/format_error.hpp"
#include "formats/pcd_reader.hpp"
#include "formats/scan_file.hpp"
#include "tests/formats/cloud_test_points.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;
using test::append;
using test::error_of;
using test::expect_known_points;
using test::kPoints;
using test::Point;

class PcdReader : public test::CloudFileTest {};

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

// The same values stored field by field, as binary_compressed holds them once expanded.
std::string pcd_by_field(const std::vector<Point>& points) {
    std::string s;
    for (const auto& p : points) append(s, p.x);
    for (const auto& p : points) append(s, p.y);
    for (const auto& p : points) append(s, p.z);
    for (const auto& p : points) append(s, p.intensity);
    for (const auto& p : points) append(s, packed(p));
    return s;
}

// A valid LZF stream: runs of 3 or more equal bytes as back references to the byte just
// written (distance 1, overlapping copy; lengths above 8 use the extra length byte), other
// bytes as literal runs of up to 32. Independent of the reader's decoder.
std::string lzf_compress(const std::string& in) {
    std::string out, literal;
    const auto flush = [&] {
        for (std::size_t k = 0; k < literal.size(); k += 32) {
            const std::size_t n = std::min<std::size_t>(32, literal.size() - k);
            out += static_cast<char>(n - 1);
            out += literal.substr(k, n);
        }
        literal.clear();
    };
    std::size_t i = 0;
    while (i < in.size()) {
        std::size_t run = 1;
        while (i + run < in.size() && in[i + run] == in[i] && run < 265) ++run;
        literal += in[i];  // the first byte of a run is written, the rest refer back to it
        ++i;
        std::size_t repeat = run - 1;
        if (repeat < 3) {
            literal.append(in, i, repeat);
            i += repeat;
            continue;
        }
        flush();
        const std::size_t len = repeat - 2;  // stored length
        if (len < 7) {
            out += static_cast<char>(len << 5);
        } else {
            out += static_cast<char>(7 << 5);
            out += static_cast<char>(len - 7);
        }
        out += '\0';  // distance 1: the byte before
        i += repeat;
    }
    flush();
    return out;
}

std::string pcd_compressed(const std::vector<Point>& cells, std::size_t width, std::size_t height) {
    const std::string plain = pcd_by_field(cells);
    const std::string packed_data = lzf_compress(plain);
    std::string s = pcd_header("binary_compressed", width, height);
    append(s, static_cast<std::uint32_t>(packed_data.size()));
    append(s, static_cast<std::uint32_t>(plain.size()));
    return s + packed_data;
}

TEST_F(PcdReader, AsciiRoundTripWithViewpoint) {
    const fs::path p = write("cloud.pcd", pcd_ascii());
    EXPECT_EQ(detect_format(p), ScanFormat::pcd);
    const Scan scan = read_scans(p).at(0);
    expect_known_points(scan, 1e-9);
    EXPECT_EQ(scan.scanner_position(), Eigen::Vector3d(10, 20, 30));
    EXPECT_FALSE(scan.grid.has_value());
}

TEST_F(PcdReader, BinaryRoundTrip) {
    const std::string bytes = pcd_header("binary", kPoints.size(), 1) + pcd_binary_records(kPoints);
    expect_known_points(read_scans(write("cloud.pcd", bytes)).at(0), 0.0);
}

TEST_F(PcdReader, BinaryCompressedRoundTrip) {
    const std::string bytes = pcd_compressed(kPoints, kPoints.size(), 1);
    expect_known_points(read_scans(write("cloud.pcd", bytes)).at(0), 0.0);
    // The same through the bytes in memory.
    expect_known_points(parse_pcd(bytes, "in-memory.pcd").at(0), 0.0);
}

TEST_F(PcdReader, CompressorUsesBackReferences) {
    // 300 zero bytes: one literal, a long reference (264 bytes), a short one (35 left).
    // 300 zero bytes: literal, reference of 264, literal, reference of 34: 2+3+2+3 bytes.
    EXPECT_EQ(lzf_compress(std::string(300, '\0')).size(), 10u);
    // Points at the origin with another in the middle: long references on both sides.
    std::vector<Point> cells(200, Point{0, 0, 0, 0.0f, 0, 0, 0});
    cells[100] = kPoints[1];
    const std::string bytes = pcd_compressed(cells, cells.size(), 1);
    EXPECT_LT(bytes.size(), pcd_header("binary_compressed", 200, 1).size() + 400u);
    const Scan scan = read_scans(write("same.pcd", bytes)).at(0);
    ASSERT_EQ(scan.size(), 200u);
    EXPECT_EQ(scan.xyz[199], Eigen::Vector3d(0, 0, 0));
    EXPECT_EQ(scan.xyz[100], Eigen::Vector3d(-1.5, 2.25, -3.125));
    EXPECT_EQ(scan.rgb[100], (Rgb8{1, 2, 3}));
    EXPECT_EQ(scan.rgb[101], (Rgb8{0, 0, 0}));
}

std::vector<Point> cells_with_a_hole() {
    std::vector<Point> cells = kPoints;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    cells.insert(cells.begin() + 1, Point{nan, nan, nan, 0.0f, 0, 0, 0});  // no return
    return cells;
}

void expect_two_by_two_grid(const Scan& scan) {
    expect_known_points(scan, 0.0);
    ASSERT_TRUE(scan.grid.has_value());
    EXPECT_EQ(scan.grid->rows, 2u);
    EXPECT_EQ(scan.grid->columns, 2u);
    // Cells in row-major order: (0,0) point 0, (0,1) empty, (1,0) point 1, (1,1) point 2.
    EXPECT_EQ(scan.grid->row, (std::vector<std::uint32_t>{0, 1, 1}));
    EXPECT_EQ(scan.grid->column, (std::vector<std::uint32_t>{0, 0, 1}));
}

TEST_F(PcdReader, OrganisedPcdKeepsItsGridAndSkipsNaNCells) {
    const std::string bytes = pcd_header("binary", 2, 2) + pcd_binary_records(cells_with_a_hole());
    expect_two_by_two_grid(read_scans(write("organised.pcd", bytes)).at(0));
    expect_two_by_two_grid(
        read_scans(write("organised_z.pcd", pcd_compressed(cells_with_a_hole(), 2, 2))).at(0));
    std::string ascii = pcd_header("ascii", 2, 2);
    for (const auto& p : cells_with_a_hole()) {
        char line[200];
        std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.9g %u\n", p.x, p.y, p.z, p.intensity,
                      packed(p));
        ascii += line;  // the hole is written "nan nan nan", as PCL does
    }
    ASSERT_NE(ascii.find("\nnan nan nan 0 0\n"), std::string::npos);
    expect_two_by_two_grid(read_scans(write("organised_ascii.pcd", ascii)).at(0));
}

TEST_F(PcdReader, ViewpointQuaternionTurnsThePose) {
    // qw = qz = sqrt(1/2): 90 degrees about z, so the pose takes x to y.
    const std::string s =
        "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n"
        "VIEWPOINT 1 2 3 0.70710678 0 0 0.70710678\nPOINTS 1\nDATA ascii\n4 5 6\n";
    const Scan scan = read_scans(write("turned.pcd", s)).at(0);
    EXPECT_TRUE(
        (scan.pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-6));
    EXPECT_EQ(scan.scanner_position(), Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(scan.xyz[0], Eigen::Vector3d(4, 5, 6));
}

TEST_F(PcdReader, AsciiFloatRgbIsTheBitPattern) {
    // An rgb field of TYPE F written as the float whose bits are 0x00FF000A (255, 0, 10).
    const std::uint32_t bits = 0x00FF000Au;
    float f;
    std::memcpy(&f, &bits, 4);
    char value[64];
    std::snprintf(value, sizeof value, "%.9g", f);
    const std::string s =
        "VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 1\n"
        "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 " +
        std::string(value) + "\n";
    const Scan scan = read_scans(write("float_rgb.pcd", s)).at(0);
    ASSERT_EQ(scan.rgb.size(), 1u);
    EXPECT_EQ(scan.rgb[0], (Rgb8{255, 0, 10}));
}

TEST_F(PcdReader, IntensityRawScaleFollowsTheFieldType) {
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

TEST_F(PcdReader, BrokenFilesAreFormatErrorsNamingTheFile) {
    std::vector<fs::path> broken;
    const std::string binary_pcd =
        pcd_header("binary", kPoints.size(), 1) + pcd_binary_records(kPoints);
    broken.push_back(write("truncated_binary.pcd", binary_pcd.substr(0, binary_pcd.size() - 9)));
    const std::string ascii_pcd = pcd_ascii();
    broken.push_back(write("truncated_ascii.pcd", ascii_pcd.substr(0, ascii_pcd.size() - 30)));
    const std::string z = pcd_compressed(kPoints, kPoints.size(), 1);
    broken.push_back(write("truncated_compressed.pcd", z.substr(0, z.size() - 3)));
    std::string damaged = z;
    const std::size_t lzf_start = pcd_header("binary_compressed", kPoints.size(), 1).size() + 8;
    damaged[lzf_start] = static_cast<char>(0xff);  // a back reference before the first byte
    const fs::path damaged_file = write("damaged_compressed.pcd", damaged);
    EXPECT_NE(error_of(damaged_file).find("LZF data damaged: back reference before the start"),
              std::string::npos)
        << error_of(damaged_file);
    broken.push_back(
        write("garbage.pcd", std::string("# .PCD v0.7\nVERSION 0.7\n\x01\x02\xff", 27)));
    broken.push_back(write("empty.pcd", ""));
    broken.push_back(write("no_xyz.pcd",
                           "VERSION 0.7\nFIELDS a\nSIZE 4\nTYPE F\nCOUNT 1\nWIDTH 1\nHEIGHT 1\n"
                           "POINTS 1\nDATA ascii\n1\n"));
    broken.push_back(dir_ / "missing.pcd");
    for (const auto& p : broken) {
        const std::string m = error_of(p);
        EXPECT_EQ(m.rfind(p.string() + ":", 0), 0u) << p << " -> \"" << m << "\"";
    }
    // ASCII lines with the wrong count or a word are errors naming the line.
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
    const fs::path many =
        write("many.pcd", header + "1 2 3 0.5 7\n1 2 3 0.5 7\n1 2 3 0.5 7\n1 2 3 0 7\n");
    EXPECT_NE(error_of(many).find("many.pcd:15: more point lines than the 3 points"),
              std::string::npos)
        << error_of(many);
}

// Header counts far beyond the file are refused before anything is allocated for them.
TEST_F(PcdReader, HugeCountsAreRefusedWithoutAllocating) {
    // A record is 8+8+8+4+4 = 32 bytes.
    const std::string h = pcd_header("binary", 4000000000u, 1);
    const fs::path binary = write("huge.pcd", h + pcd_binary_records(kPoints));
    EXPECT_NE(error_of(binary).find("at byte " + std::to_string(h.size()) +
                                    ": header declares 4000000000 points of 32 bytes"),
              std::string::npos)
        << error_of(binary);
    const fs::path ascii =
        write("huge_ascii.pcd", pcd_header("ascii", 4000000000u, 1) + "1 2 3 0 0\n");
    EXPECT_NE(error_of(ascii).find("huge_ascii.pcd:13: file ends after 1 points"),
              std::string::npos)
        << error_of(ascii);
    // A COUNT no line of the file could hold.
    const fs::path wide = write("wide.pcd",
                                "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                                "COUNT 1 1 4000000000\nWIDTH 1\nDATA ascii\n1 2 3\n");
    EXPECT_NE(error_of(wide).find("a point line of 4000000002 values needs more than the 6 bytes"),
              std::string::npos)
        << error_of(wide);
    // binary_compressed claiming a small file expands to a lot.
    std::string z = pcd_header("binary_compressed", 1000000, 1);
    append(z, std::uint32_t{2}), append(z, std::uint32_t{32000000});
    z += std::string("\x00\x01", 2);
    const fs::path bomb = write("bomb.pcd", z);
    EXPECT_NE(error_of(bomb).find("compressed size 2 cannot expand"), std::string::npos)
        << error_of(bomb);
}

}  // namespace
}  // namespace tlsmon
