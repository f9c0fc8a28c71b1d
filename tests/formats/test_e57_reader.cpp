// E57 reader on the real files of ../shared/data/e57 (expected values from INVENTORY.md)
// and on files written by e57_writer for what the real files do not cover.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/utc_time.hpp"
#include "formats/e57_reader.hpp"
#include "formats/e57_writer.hpp"
#include "formats/format_error.hpp"
#include "formats/ptx_reader.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

const std::filesystem::path e57_dir = std::filesystem::path(TLSMON_DATA_DIR) / "e57";
const std::filesystem::path pump_file = e57_dir / "pumpARowColumnIndexNoInvalidPoints.e57";
const std::filesystem::path self_dir = e57_dir / "libE57Format-test-data" / "self";

Scan read_one(const std::filesystem::path& path) {
    std::vector<Scan> scans = read_e57(path);
    EXPECT_EQ(scans.size(), 1u) << path;
    return scans.empty() ? Scan{} : std::move(scans.front());
}

double max_abs_difference(const Scan& a, const Scan& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        d = std::max(d, (a.xyz[i] - b.xyz[i]).cwiseAbs().maxCoeff());
    return d;
}

// The FormatError text of reading `path`, or "" when it reads.
std::string error_of(const std::filesystem::path& path) {
    try {
        read_e57(path);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

TEST(E57Reader, PumpScanIsA1074By345GridOf155201Points) {
    const Scan s = read_one(pump_file);
    EXPECT_EQ(s.name, "pumpsA");
    EXPECT_EQ(s.source, pump_file.string());
    ASSERT_EQ(s.size(), 155201u);
    ASSERT_EQ(s.intensity.size(), s.size());
    ASSERT_EQ(s.rgb.size(), s.size());
    ASSERT_TRUE(s.grid.has_value());
    EXPECT_EQ(s.grid->rows, 1074u);
    EXPECT_EQ(s.grid->columns, 345u);
    ASSERT_EQ(s.grid->row.size(), s.size());
    // 41.9 % of the cells hold a point, each cell at most one.
    std::set<std::uint64_t> cells;
    for (std::size_t i = 0; i < s.size(); ++i)
        cells.insert(std::uint64_t{s.grid->row[i]} * s.grid->columns + s.grid->column[i]);
    EXPECT_EQ(cells.size(), s.size());
    EXPECT_NEAR(static_cast<double>(s.size()) / static_cast<double>(s.grid->cells()), 0.419, 0.001);

    // Identity pose: ranges and angles inside the file's sphericalBounds and reaching them.
    EXPECT_TRUE(s.pose.matrix().isIdentity());
    double r_min = 1e9, r_max = 0, az_min = 9, az_max = -9, el_min = 9, el_max = -9;
    for (const auto& p : s.xyz) {
        const double r = p.norm();
        r_min = std::min(r_min, r);
        r_max = std::max(r_max, r);
        az_min = std::min(az_min, std::atan2(p.y(), p.x()));
        az_max = std::max(az_max, std::atan2(p.y(), p.x()));
        el_min = std::min(el_min, std::asin(p.z() / r));
        el_max = std::max(el_max, std::asin(p.z() / r));
    }
    EXPECT_GE(r_min, 1.982999 - 1e-6);
    EXPECT_LT(r_min, 1.99);
    EXPECT_LE(r_max, 5.429336 + 1e-6);
    EXPECT_GT(r_max, 5.42);
    EXPECT_NEAR(az_min, -2.58, 0.005);
    EXPECT_NEAR(az_max, -1.08, 0.005);
    EXPECT_NEAR(el_min, -0.785, 0.005);
    EXPECT_NEAR(el_max, 0.481, 0.005);

    // Intensity limits 0..1 (ScaledInteger 32767 * 1/32767): normalised = raw value.
    EXPECT_NEAR(s.intensity_raw_min, 0.0, 1e-12);
    EXPECT_NEAR(s.intensity_raw_max, 1.0, 1e-12);
    const auto [i_min, i_max] = std::minmax_element(s.intensity.begin(), s.intensity.end());
    EXPECT_NEAR(*i_min, 0.384, 0.001);
    EXPECT_NEAR(*i_max, 0.698, 0.001);
    // The bounding box is the file's cartesianBounds (xMinimum -2.903764 ... zMaximum 1.843003)
    // within one count (1e-6 m): the exporter rounded the bounds separately.
    Eigen::Vector3d lo = s.xyz[0], hi = s.xyz[0];
    for (const auto& p : s.xyz) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    EXPECT_LE((lo - Eigen::Vector3d(-2.903764, -5.301103, -1.899705)).cwiseAbs().maxCoeff(),
              1e-6 + 1e-12);
    EXPECT_LE((hi - Eigen::Vector3d(1.721604, -0.792647, 1.843003)).cwiseAbs().maxCoeff(),
              1e-6 + 1e-12);
    // First record of the file, as the PTX export of the same scan prints it.
    EXPECT_NEAR(s.xyz[0].x(), 1.702286, 1e-9);
    EXPECT_NEAR(s.xyz[0].y(), -3.193588, 1e-9);
    EXPECT_NEAR(s.xyz[0].z(), -1.841843, 1e-9);
    EXPECT_EQ(s.rgb[0], (Rgb8{51, 65, 49}));
}

TEST(E57Reader, PumpWithGroupingAndImageEqualsThePlainPumpWithin1Micrometre) {
    const Scan a = read_one(pump_file);
    const Scan b = read_one(e57_dir / "pye57" / "pumpAVisualReferenceImage.e57");
    ASSERT_EQ(b.size(), 155201u);
    ASSERT_EQ(a.size(), b.size());
    std::size_t off_by_rounding = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double d = (a.xyz[i] - b.xyz[i]).cwiseAbs().maxCoeff();
        ASSERT_LE(d, 1e-6 + 1e-12) << "point " << i;
        if (d > 0.5e-6) ++off_by_rounding;
        ASSERT_EQ(a.grid->row[i], b.grid->row[i]);
        ASSERT_EQ(a.grid->column[i], b.grid->column[i]);
        ASSERT_EQ(a.intensity[i], b.intensity[i]);
        ASSERT_EQ(a.rgb[i], b.rgb[i]);
    }
    EXPECT_EQ(off_by_rounding, 6112u);
}

// pumpA_from_e57.ptx is the same scan written as PTX with 6 decimals. PTX row k of a
// column is E57 rowIndex k: the rows are NOT flipped (checked point by point below), and
// the points come in the same order (column by column, the order of the E57 records).
TEST(E57Reader, PumpScanEqualsItsPtxExportCellByCell) {
    const Scan e = read_one(pump_file);
    const std::vector<Scan> ptx =
        read_ptx(std::filesystem::path(TLSMON_DATA_DIR) / "ptx" / "pumpA_from_e57.ptx");
    ASSERT_EQ(ptx.size(), 1u);
    const Scan& p = ptx[0];
    ASSERT_EQ(p.size(), 155201u);
    ASSERT_EQ(e.size(), p.size());
    ASSERT_TRUE(p.grid.has_value());
    EXPECT_EQ(e.grid->rows, p.grid->rows);
    EXPECT_EQ(e.grid->columns, p.grid->columns);
    for (std::size_t i = 0; i < e.size(); ++i) {
        ASSERT_EQ(e.grid->row[i], p.grid->row[i]) << "point " << i;
        ASSERT_EQ(e.grid->column[i], p.grid->column[i]) << "point " << i;
        ASSERT_LE((e.xyz[i] - p.xyz[i]).cwiseAbs().maxCoeff(), 1e-6) << "point " << i;
        ASSERT_EQ(e.rgb[i], p.rgb[i]) << "point " << i;
        // Intensity: the E57 value is k / 32767 (ScaledInteger); the PTX holds it printed
        // with %.6f. Recover k, print it the same way: the PTX value exactly.
        const double k = std::round(static_cast<double>(e.intensity[i]) * 32767.0);
        ASSERT_NEAR(static_cast<double>(e.intensity[i]), k / 32767.0, 1e-7);
        char text[32];
        std::snprintf(text, sizeof text, "%.6f", k * 3.0518509475997192e-05);
        ASSERT_EQ(std::strtof(text, nullptr), p.intensity[i]) << "point " << i;
        // Stored as float: within the PTX's rounding (5e-7) plus float resolution.
        ASSERT_NEAR(e.intensity[i], p.intensity[i], 5e-7 + 6e-8) << "point " << i;
    }
}

TEST(E57Reader, BunnyInFloatDoubleAndScaledIntegerAgree) {
    const Scan f = read_one(e57_dir / "bunnyFloat.e57");
    const Scan d = read_one(e57_dir / "libE57Format-test-data" / "reference" / "bunnyDouble.e57");
    const Scan i = read_one(e57_dir / "libE57Format-test-data" / "reference" / "bunnyInt32.e57");
    EXPECT_EQ(f.name, "bunny");
    ASSERT_EQ(f.size(), 30571u);
    ASSERT_EQ(d.size(), 30571u);
    ASSERT_EQ(i.size(), 30571u);
    // Coarsest precision: ScaledInteger 1e-6 m (half a count of rounding).
    EXPECT_LE(max_abs_difference(f, i), 0.5e-6);
    EXPECT_LE(max_abs_difference(d, i), 0.5e-6);
    // Float32 at |x| < 0.19 m resolves 1.5e-8 m.
    EXPECT_LE(max_abs_difference(f, d), 2e-8);
    // cartesianBounds of the file.
    double x_min = 1, x_max = -1;
    for (const auto& p : d.xyz) {
        x_min = std::min(x_min, p.x());
        x_max = std::max(x_max, p.x());
    }
    EXPECT_DOUBLE_EQ(x_min, -0.094689);
    EXPECT_DOUBLE_EQ(x_max, 0.061009);
}

TEST(E57Reader, ColouredCubeFloatAndDoubleGiveTheSamePointsAndColours) {
    const Scan f = read_one(self_dir / "ColouredCubeFloat.e57");
    const Scan d = read_one(self_dir / "ColouredCubeDouble.e57");
    ASSERT_EQ(f.size(), 7680u);
    ASSERT_EQ(d.size(), 7680u);
    ASSERT_EQ(f.rgb.size(), 7680u);
    EXPECT_LE(max_abs_difference(f, d), 1e-7);
    std::set<Rgb8> colours(f.rgb.begin(), f.rgb.end());
    EXPECT_EQ(colours, (std::set<Rgb8>{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}}));
    EXPECT_EQ(f.rgb, d.rgb);
    for (const auto& p : f.xyz) EXPECT_LE(p.cwiseAbs().maxCoeff(), 0.5);
}

TEST(E57Reader, SixteenBitColourFromLas2e57IsScaledTo8Bits) {
    const Scan s = read_one(e57_dir / "libE57Format-test-data" / "3rdParty" / "las2e57" /
                            "ColourRepresentation.e57");
    ASSERT_EQ(s.size(), 153u);
    ASSERT_EQ(s.rgb.size(), 153u);
    // LAS 8-bit 255 written as 16-bit 65280 comes back as 255.
    std::set<Rgb8> colours(s.rgb.begin(), s.rgb.end());
    EXPECT_EQ(colours, (std::set<Rgb8>{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}}));
    EXPECT_DOUBLE_EQ(s.xyz[0].x(), -0.5);
    EXPECT_DOUBLE_EQ(s.xyz[0].y(), -0.015);
}

TEST(E57Reader, FilesWithoutPointsOpen) {
    const Scan zero = read_one(self_dir / "ZeroPoints.e57");
    EXPECT_EQ(zero.size(), 0u);
    for (const char* name : {"empty.e57", "test filename äöü.e57", "测试点云.e57",
                             "PinholeImageWithDistortionParameters.e57"})
        EXPECT_TRUE(read_e57(self_dir / name).empty()) << name;
}

TEST(E57Reader, ExtensionFieldsAreSkipped) {
    const Scan s = read_one(e57_dir / "pye57" / "testWithNormals.e57");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.name, "dummyWithNormals - Cloud");
    EXPECT_TRUE(s.xyz[0].isApprox(Eigen::Vector3d(1, 0, 0)));
    EXPECT_TRUE(s.xyz[1].isApprox(Eigen::Vector3d(2, 0, 0)));
}

TEST(E57Reader, TranslationWithoutRotationIsAppliedWithIdentityRotation) {
    const Scan s = read_one(e57_dir / "pye57" / "translationWithoutRotation.e57");
    ASSERT_EQ(s.size(), 4u);
    EXPECT_TRUE(s.pose.linear().isIdentity());
    EXPECT_TRUE(s.scanner_position().isApprox(Eigen::Vector3d(4, 5, 6)));
    // Stored 0..1 in the scanner frame; the file's cartesianBounds are 4..5, 5..6, 6.
    const std::vector<Eigen::Vector3d> expected = {{4, 5, 6}, {5, 5, 6}, {4, 6, 6}, {5, 6, 6}};
    for (std::size_t i = 0; i < 4; ++i) EXPECT_TRUE(s.xyz[i].isApprox(expected[i])) << i;
}

TEST(E57Reader, DamagedFilesFailWithSpecificErrorsNamingFileAndByte) {
    struct Case {
        std::filesystem::path file;
        std::string where;
        std::string what;
    };
    const std::vector<Case> cases = {
        {e57_dir / "InvalidFileLength.e57", "at byte 120",
         "file length 120 bytes is not a multiple of the 1024-byte E57 page"},
        {e57_dir / "NoPrototype.e57", "at byte 813",
         "bad prototype: compressed vector <points> has no <prototype>"},
        {self_dir / "bad-crc.e57", "at byte 1020", "bad checksum of page 0: stored 0x1392e413"},
        {self_dir / "InvalidCVHeader.e57", "at byte 48",
         "bad compressed-vector section header: section id 182, expected 1"},
        {self_dir / "ZeroPointsInvalid.e57", "at byte 1164",
         "invalid zero-record data: compressed vector with 0 records has fileOffset 0"},
    };
    for (const Case& c : cases) {
        const std::string e = error_of(c.file);
        EXPECT_NE(e.find(c.file.string() + ": " + c.where + ": "), std::string::npos) << e;
        EXPECT_NE(e.find(c.what), std::string::npos) << e;
    }
}

TEST(E57Reader, ReadScansDispatchesE57) {
    const std::vector<Scan> scans = read_scans(pump_file);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].size(), 155201u);
}

TEST(E57Reader, GpsTimeIsConvertedToUtcWithLeapSeconds) {
    EXPECT_DOUBLE_EQ(gps_to_utc(0.0), 315964800.0);  // 1980-01-06T00:00:00Z
    // 2017-01-01T00:00:00Z = Unix 1483228800; GPS - UTC = 18 s from then on, 17 s before.
    EXPECT_DOUBLE_EQ(gps_to_utc(1483228800.0 - 315964800.0 + 18), 1483228800.0);
    EXPECT_DOUBLE_EQ(gps_to_utc(1483228799.0 - 315964800.0 + 17), 1483228799.0);
    // 1999-01-01: 13 s.
    EXPECT_DOUBLE_EQ(gps_to_utc(915148800.0 - 315964800.0 + 13), 915148800.0);
}

// Files the real data set lacks: several scans, a rotated pose, spherical coordinates,
// invalid records, an acquisition time; written by e57_writer, read back.
class E57RoundTrip : public ::testing::Test {
  protected:
    static Scan grid_scan(std::uint32_t rows, std::uint32_t columns, double shift) {
        Scan s;
        s.name = "synthetic";
        s.pose = Eigen::Translation3d(10.0, -20.0, 5.0 + shift) *
                 Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 0.3, 1.0).normalized());
        s.grid = ScanGrid{rows, columns, {}, {}};
        for (std::uint32_t c = 0; c < columns; ++c)
            for (std::uint32_t r = 0; r < rows; ++r) {
                if ((r + c) % 3 == 0) continue;  // empty cells
                const double az = 0.01 * c, el = -0.5 + 0.01 * r,
                             range = 3.0 + 0.001 * (r * c % 97);
                const Eigen::Vector3d local(range * std::cos(el) * std::cos(az),
                                            range * std::cos(el) * std::sin(az),
                                            range * std::sin(el));
                s.xyz.push_back(s.pose * local);
                s.intensity.push_back(static_cast<float>((r * 7 + c) % 4096) / 4095.0f);
                s.rgb.push_back({static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(c), 7});
                s.grid->row.push_back(r);
                s.grid->column.push_back(c);
            }
        s.acquired_utc = 1700000000.0 + shift;
        return s;
    }

    void expect_same(const Scan& written, const Scan& read, double tolerance) {
        ASSERT_EQ(read.size(), written.size());
        EXPECT_EQ(read.name, written.name);
        EXPECT_TRUE(read.pose.matrix().isApprox(written.pose.matrix(), 1e-12));
        EXPECT_LE(max_abs_difference(written, read), tolerance);
        EXPECT_EQ(read.rgb, written.rgb);
        ASSERT_TRUE(read.grid.has_value());
        EXPECT_EQ(read.grid->rows, written.grid->rows);
        EXPECT_EQ(read.grid->columns, written.grid->columns);
        EXPECT_EQ(read.grid->row, written.grid->row);
        EXPECT_EQ(read.grid->column, written.grid->column);
        ASSERT_EQ(read.intensity.size(), written.intensity.size());
        for (std::size_t i = 0; i < read.size(); ++i)
            ASSERT_NEAR(read.intensity[i], written.intensity[i], 0.5f / 4095.0f + 1e-6f);
        ASSERT_TRUE(read.acquired_utc.has_value());
        EXPECT_NEAR(*read.acquired_utc, *written.acquired_utc, 1e-6);
    }

    test::TempDir dir_;
};

TEST_F(E57RoundTrip, SeveralScansWithRotatedPoseScaledIntegerAndInvalidRecords) {
    const std::vector<Scan> written = {grid_scan(50, 40, 0.0), grid_scan(7, 300, 1.0)};
    const auto file = dir_ / "two.e57";
    write_e57(file, written, {.coordinate_scale = 1e-4, .spherical = false, .invalid_every = 5});
    const std::vector<Scan> read = read_e57(file);
    ASSERT_EQ(read.size(), 2u);
    EXPECT_EQ(read[0].source, file.string() + "#1");
    EXPECT_EQ(read[1].source, file.string() + "#2");
    // Half a count per scanner axis, rotated into the project frame: at most sqrt(3) / 2 counts.
    for (int k = 0; k < 2; ++k) expect_same(written[k], read[k], std::sqrt(3.0) * 0.5e-4 + 1e-9);
    // The header-only look-up gives the first scan's time without decoding points.
    const std::optional<double> t = read_e57_acquired_utc(file);
    ASSERT_TRUE(t.has_value());
    EXPECT_NEAR(*t, *written[0].acquired_utc, 1e-6);
    EXPECT_FALSE(read_e57_acquired_utc(pump_file).has_value());
}

TEST_F(E57RoundTrip, SphericalCoordinatesAreConvertedToCartesian) {
    const std::vector<Scan> written = {grid_scan(30, 20, 0.0)};
    const auto file = dir_ / "spherical.e57";
    write_e57(file, written, {.coordinate_scale = 0.0, .spherical = true, .invalid_every = 3});
    expect_same(written[0], read_one(file), 1e-9);
}

// A region cut out of a large scan keeps its place in that scan's grid: 3266 points at rows
// 10⁹ and columns 2·10⁹ of a grid of 2³² − 1 by 2³² − 1 cells. Taken at its word, that grid
// would be 1.8·10¹⁹ cells; the reader cuts it to the 70 by 70 cells the points occupy,
// keeping every point's neighbours in the grid.
TEST_F(E57RoundTrip, ARegionCutOutOfALargeGridKeepsOnlyTheCellsItOccupies) {
    const Scan region = grid_scan(70, 70, 0.0);
    Scan placed = region;
    placed.grid->rows = placed.grid->columns = 0xFFFFFFFFu;
    for (auto& r : placed.grid->row) r += 1'000'000'000u;
    for (auto& c : placed.grid->column) c += 2'000'000'000u;
    const auto file = dir_ / "region.e57";
    write_e57(file, {placed}, {.coordinate_scale = 0.0});
    const Scan read = read_one(file);
    ASSERT_TRUE(read.grid.has_value());
    EXPECT_EQ(read.grid->rows, 70u);
    EXPECT_EQ(read.grid->columns, 70u);
    EXPECT_EQ(read.grid->row, region.grid->row);
    EXPECT_EQ(read.grid->column, region.grid->column);

    // A grid as large as the declared one but filled within its bounds is read as it is.
    const auto whole = dir_ / "whole.e57";
    write_e57(whole, {region}, {.coordinate_scale = 0.0});
    EXPECT_EQ(read_one(whole).grid->rows, 70u);
}

// Points scattered over a grid far larger than they fill are no scanner's grid: refused with
// the file and what is wrong, not taken as 10¹⁸ cells that the grid's users would allocate.
TEST_F(E57RoundTrip, PointsScatteredOverAHugeGridAreRefused) {
    Scan scattered = grid_scan(10, 10, 0.0);
    scattered.grid->rows = scattered.grid->columns = 2'000'000'000u;
    for (std::size_t i = 0; i < scattered.size(); ++i) {
        scattered.grid->row[i] *= 100'000'000u;
        scattered.grid->column[i] *= 100'000'000u;
    }
    const auto file = dir_ / "scattered.e57";
    write_e57(file, {scattered}, {.coordinate_scale = 0.0});
    const std::string e = error_of(file);
    EXPECT_NE(e.find(file.string() + ": at byte "), std::string::npos) << e;
    EXPECT_NE(e.find("rowIndex/columnIndex spread 66 points over 900000001 rows and 900000001 "
                     "columns, more than 32 cells a point: not a scanner's grid"),
              std::string::npos)
        << e;
}

TEST_F(E57RoundTrip, TruncatedAndCorruptedFilesFail) {
    const auto file = dir_ / "big.e57";
    write_e57(file, {grid_scan(100, 100, 0.0)}, {.coordinate_scale = 1e-4});
    const auto size = std::filesystem::file_size(file);
    ASSERT_GT(size, 4 * 1024u);

    const auto truncated = dir_ / "truncated.e57";
    std::filesystem::copy_file(file, truncated);
    std::filesystem::resize_file(truncated, size - 1024);
    EXPECT_NE(error_of(truncated).find(truncated.string() + ": at byte " +
                                       std::to_string(size - 1024) + ": truncated file"),
              std::string::npos)
        << error_of(truncated);

    // One flipped bit in page 2 (inside the point data) is caught by that page's CRC.
    const auto flipped = dir_ / "flipped.e57";
    std::filesystem::copy_file(file, flipped);
    {
        std::fstream f(flipped, std::ios::binary | std::ios::in | std::ios::out);
        f.seekg(2 * 1024 + 100);
        char c = 0;
        f.read(&c, 1);
        c = static_cast<char>(c ^ 0x10);
        f.seekp(2 * 1024 + 100);
        f.write(&c, 1);
    }
    const std::string e = error_of(flipped);
    EXPECT_NE(e.find(flipped.string() + ": at byte " + std::to_string(2 * 1024 + 1020) +
                     ": bad checksum of page 2"),
              std::string::npos)
        << e;
}

}  // namespace
}  // namespace tlsmon
