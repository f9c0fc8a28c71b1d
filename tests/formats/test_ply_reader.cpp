// PLY: files written here byte by byte with known points (ascii, both binary byte orders,
// list properties and other elements to skip, PCL's camera element), read back through
// read_scans; broken copies rejected with the file and the place named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "formats/format_error.hpp"
#include "formats/ply_reader.hpp"
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

class PlyReader : public test::CloudFileTest {};

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

std::string ply_binary(bool big_endian = false) {
    std::string s =
        ply_header(big_endian ? "binary_big_endian" : "binary_little_endian", kPoints.size());
    for (const auto& p : kPoints) {
        append(s, p.x, big_endian), append(s, p.y, big_endian), append(s, p.z, big_endian);
        append(s, p.intensity, big_endian);
        append(s, p.r), append(s, p.g), append(s, p.b);
    }
    return s;
}

TEST_F(PlyReader, AsciiRoundTrip) {
    const fs::path p = write("cloud.ply", ply_ascii());
    EXPECT_EQ(detect_format(p), ScanFormat::ply);
    const auto scans = read_scans(p);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].source, p.string());
    expect_known_points(scans[0], 1e-9);
    EXPECT_FALSE(scans[0].grid.has_value());
}

TEST_F(PlyReader, BinaryLittleEndianRoundTrip) {
    expect_known_points(read_scans(write("cloud.ply", ply_binary())).at(0), 0.0);
}

TEST_F(PlyReader, BinaryBigEndianRoundTrip) {
    const std::string bytes = ply_binary(true);
    // The first x as written: 637012.24's bytes reversed, so a reader that ignored the byte
    // order would read something else entirely.
    expect_known_points(read_scans(write("cloud.ply", bytes)).at(0), 0.0);
}

TEST_F(PlyReader, ParseFromBytesNeedsNoFile) {
    const auto scans = parse_ply(ply_binary(), "never-written.ply");
    expect_known_points(scans.at(0), 0.0);
    EXPECT_EQ(scans[0].source, "never-written.ply");
}

TEST_F(PlyReader, ListPropertiesAndOtherElementsAreSkipped) {
    // A face element before the vertices, a list inside each vertex, float coordinates,
    // uchar intensity (raw scale 0..255), no colour, and ushort colour absent.
    std::string header =
        "ply\nformat binary_little_endian 1.0\nelement face 2\n"
        "property list uchar int vertex_indices\nelement vertex 2\nproperty float x\n"
        "property list uchar ushort tags\nproperty float y\nproperty float z\n"
        "property uchar intensity\nend_header\n";
    std::string s = header;
    append(s, std::uint8_t{3}), append(s, 0), append(s, 1), append(s, 2);  // face 0
    append(s, std::uint8_t{0});                                            // face 1: empty
    append(s, 1.5f), append(s, std::uint8_t{2}), append(s, std::uint16_t{7}),
        append(s, std::uint16_t{8});
    append(s, 2.5f), append(s, 3.5f), append(s, std::uint8_t{51});
    append(s, -4.0f), append(s, std::uint8_t{0});
    append(s, 5.0f), append(s, 6.0f), append(s, std::uint8_t{255});
    const Scan b = read_scans(write("lists.ply", s)).at(0);
    ASSERT_EQ(b.size(), 2u);
    EXPECT_EQ(b.xyz[0], Eigen::Vector3d(1.5, 2.5, 3.5));
    EXPECT_EQ(b.xyz[1], Eigen::Vector3d(-4.0, 5.0, 6.0));
    EXPECT_EQ(b.intensity_raw_max, 255.0);
    EXPECT_FLOAT_EQ(b.intensity[0], 0.2f);
    EXPECT_FLOAT_EQ(b.intensity[1], 1.0f);
    EXPECT_TRUE(b.rgb.empty());

    const std::string ascii =
        "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
        "element vertex 2\nproperty float x\nproperty list uchar ushort tags\n"
        "property float y\nproperty float z\nproperty uchar intensity\nend_header\n"
        "3 0 1 2\n1.5 2 7 8 2.5 3.5 51\n-4 0 5 6 255\n";
    const Scan a = read_scans(write("lists_ascii.ply", ascii)).at(0);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a.xyz[1], Eigen::Vector3d(-4.0, 5.0, 6.0));
    EXPECT_FLOAT_EQ(a.intensity[0], 0.2f);
}

TEST_F(PlyReader, CloudCompareScalarIntensityOutside01UsesTheDataRange) {
    const std::string s =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty float scalar_Intensity\nend_header\n"
        "1 2 3 -100\n4 5 6 300\n7 8 9 0\n";
    const Scan scan = read_scans(write("cc.ply", s)).at(0);
    EXPECT_EQ(scan.intensity_raw_min, -100.0);
    EXPECT_EQ(scan.intensity_raw_max, 300.0);
    EXPECT_FLOAT_EQ(scan.intensity[2], 0.25f);  // (0 - -100) / 400
}

// PCL's camera element after the vertices: the viewpoint becomes the pose, and a viewport
// of width × height equal to the vertex count makes the cloud organised (row-major).
TEST_F(PlyReader, CameraElementGivesPoseAndOrganisedGrid) {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement camera 1\nproperty float view_px\n"
        "property float view_py\nproperty float view_pz\nproperty float x_axisx\n"
        "property float x_axisy\nproperty float x_axisz\nproperty float y_axisx\n"
        "property float y_axisy\nproperty float y_axisz\nproperty float z_axisx\n"
        "property float z_axisy\nproperty float z_axisz\nproperty float focal\n"
        "property int viewportx\nproperty int viewporty\nend_header\n";
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float cells[4][3] = {{1, 2, 3}, {nan, nan, nan}, {4, 5, 6}, {7, 8, 9}};
    for (const auto& c : cells) append(s, c[0]), append(s, c[1]), append(s, c[2]);
    // 90 degrees about z: the rows are x_axis = (0 1 0), y_axis = (-1 0 0), z_axis = (0 0 1).
    for (float v : {10.f, 20.f, 30.f, 0.f, 1.f, 0.f, -1.f, 0.f, 0.f, 0.f, 0.f, 1.f, 0.f}) {
        append(s, v);
    }
    append(s, std::int32_t{2}), append(s, std::int32_t{2});
    const Scan scan = read_scans(write("camera.ply", s)).at(0);
    ASSERT_EQ(scan.size(), 3u);
    EXPECT_EQ(scan.xyz[1], Eigen::Vector3d(4, 5, 6));  // not transformed: recorded only
    EXPECT_EQ(scan.scanner_position(), Eigen::Vector3d(10, 20, 30));
    EXPECT_TRUE(scan.pose.linear().row(0).isApprox(Eigen::RowVector3d(0, 1, 0), 1e-6))
        << scan.pose.linear();
    ASSERT_TRUE(scan.grid.has_value());
    EXPECT_EQ(scan.grid->rows, 2u);
    EXPECT_EQ(scan.grid->columns, 2u);
    EXPECT_EQ(scan.grid->row, (std::vector<std::uint32_t>{0, 1, 1}));
    EXPECT_EQ(scan.grid->column, (std::vector<std::uint32_t>{0, 0, 1}));
}

TEST_F(PlyReader, BrokenFilesAreFormatErrorsNamingTheFile) {
    std::vector<fs::path> broken;
    const std::string binary_ply = ply_binary();
    broken.push_back(write("truncated_binary.ply", binary_ply.substr(0, binary_ply.size() - 9)));
    const std::string big_ply = ply_binary(true);
    broken.push_back(write("truncated_big.ply", big_ply.substr(0, big_ply.size() - 1)));
    const std::string ascii_ply = ply_ascii();
    broken.push_back(write("truncated_ascii.ply", ascii_ply.substr(0, ascii_ply.size() - 30)));
    broken.push_back(write("bad_header.ply", "ply\nformat unknown 1.0\nend_header\n1 2 3\n"));
    broken.push_back(write("header_only.ply", "ply\nformat ascii 1.0\nelement vertex 5\n"));
    broken.push_back(write("no_xyz.ply",
                           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\n"
                           "end_header\n1\n"));
    broken.push_back(write("empty.ply", ""));
    broken.push_back(write("garbage.ply", std::string("ply\n\x01\x02\xff\x00", 8)));
    broken.push_back(dir_ / "missing.ply");
    for (const auto& p : broken) {
        const std::string m = error_of(p);
        EXPECT_EQ(m.rfind(p.string() + ":", 0), 0u) << p << " -> \"" << m << "\"";
    }
}

TEST_F(PlyReader, ErrorsNameTheLineOrByte) {
    // Header: 12 lines; the second vertex line (14) has a word where a number belongs.
    fs::path p = write("word.ply", ply_header("ascii", 2) + "1 2 3 0.5 1 2 3\n1 2 x 0.5 1 2 3\n");
    EXPECT_NE(error_of(p).find("word.ply:14: \"x\" is not a number"), std::string::npos)
        << error_of(p);
    p = write("short.ply", ply_header("ascii", 2) + "1.000 2.000 3.000\n1 2 3 0.5 1 2 3\n");
    EXPECT_NE(error_of(p).find("short.ply:13: 3 values, the header declares 7 per vertex"),
              std::string::npos)
        << error_of(p);
    p = write("few.ply", ply_header("ascii", 3) + "1 2 3 0.5 1 2 3\n\n");
    EXPECT_NE(error_of(p).find("few.ply:15: file ends after 1 of the 3 vertex lines"),
              std::string::npos)
        << error_of(p);
    // 3 records of 8+8+8+4+1+1+1 = 31 bytes follow the header; 2 bytes are missing.
    const std::string bin = ply_binary();
    p = write("cut.ply", bin.substr(0, bin.size() - 2));
    EXPECT_NE(error_of(p).find("cut.ply:4: element vertex declares 3 records of at least 31 "
                               "bytes, but only 91 bytes follow"),
              std::string::npos)
        << error_of(p);
}

// A header count far beyond the file is refused before anything is allocated for it
// (binary), or reserved only as far as the bytes can hold and then found short (ascii).
TEST_F(PlyReader, HugeVertexCountIsRefusedWithoutAllocating) {
    const auto huge = [](const char* format) {
        std::string h = ply_header(format, 0);
        return h.replace(h.find("vertex 0"), 8, "vertex 18446744073709551615");
    };
    fs::path p = write("huge.ply", huge("binary_little_endian") + "1 2 3 0.5 1 2 3\n");
    EXPECT_NE(error_of(p).find("huge.ply:4: element vertex declares 18446744073709551615 records"),
              std::string::npos)
        << error_of(p);
    p = write("huge_ascii.ply", huge("ascii") + "1 2 3 0.5 1 2 3\n");
    EXPECT_NE(error_of(p).find("huge_ascii.ply:14: file ends after 1 of the 18446744073709551615"),
              std::string::npos)
        << error_of(p);
}

TEST_F(PlyReader, NegativeListLengthIsAnError) {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty list char int l\n"
        "property float x\nproperty float y\nproperty float z\nend_header\n";
    append(s, std::int8_t{-1}), append(s, 1.f), append(s, 2.f), append(s, 3.f);
    const fs::path p = write("negative.ply", s);
    EXPECT_NE(error_of(p).find("negative list length"), std::string::npos) << error_of(p);
}

}  // namespace
}  // namespace tlsmon
