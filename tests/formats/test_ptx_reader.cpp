// PTX reader on the real files of ../shared/data/ptx (expected values from its
// INVENTORY.md) and on broken copies of them made in a temporary folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>

#include "formats/format_error.hpp"
#include "formats/ptx_reader.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/rejected_files.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;
using tlsmon::FormatError;
using tlsmon::read_ptx;
using tlsmon::Scan;

namespace {

const fs::path data = fs::path(TLSMON_DATA_DIR) / "ptx";

class PtxBroken : public tlsmon::test::RejectedFiles {};

// no-color.ptx with its text replaced: line `n` (1-based) becomes `text`.
std::string no_color_with_line(int n, const std::string& text) {
    std::istringstream in(tlsmon::test::read_file(data / "no-color.ptx"));
    std::string out, line;
    for (int k = 1; std::getline(in, line); ++k) out += (k == n ? text : line) + "\n";
    return out;
}

std::string error_of(const fs::path& p) {
    try {
        read_ptx(p);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(PtxReader, NoColorHasFifteenPointsInOneRow) {
    const auto scans = read_ptx(data / "no-color.ptx");
    ASSERT_EQ(scans.size(), 1u);
    const Scan& s = scans[0];
    EXPECT_EQ(s.size(), 15u);
    EXPECT_TRUE(s.rgb.empty());
    ASSERT_TRUE(s.grid);
    EXPECT_EQ(s.grid->rows, 1u);
    EXPECT_EQ(s.grid->columns, 15u);
    EXPECT_EQ(s.grid->column[14], 14u);
    EXPECT_NEAR(s.xyz[0].x(), 637012.24, 1e-6);
    EXPECT_NEAR(s.xyz[14].z(), 426.61, 1e-6);
    ASSERT_EQ(s.intensity.size(), 15u);
    EXPECT_FLOAT_EQ(s.intensity[0], 0.034912f);
    EXPECT_EQ(s.intensity_raw_min, 0.0);
    EXPECT_EQ(s.intensity_raw_max, 1.0);
    EXPECT_TRUE(s.pose.matrix().isIdentity());
    EXPECT_EQ(s.source, (data / "no-color.ptx").string());
}

TEST(PtxReader, BothScansOfMultipleAndTransformGiveTheSamePoints) {
    const auto scans = read_ptx(data / "multiple-and-transform.ptx");
    ASSERT_EQ(scans.size(), 2u);
    for (const Scan& s : scans) {
        ASSERT_EQ(s.size(), 4u);
        EXPECT_NEAR(s.xyz[0].x(), 637012.24, 1e-6);
        EXPECT_NEAR(s.xyz[0].y(), 849028.31, 1e-6);
        EXPECT_NEAR(s.xyz[0].z(), 431.66, 1e-6);
    }
    for (int k = 0; k < 4; ++k) EXPECT_LT((scans[0].xyz[k] - scans[1].xyz[k]).norm(), 1e-6);
    // The first scan's transform has a z scale of 2 and translation (600000, 800000, 400).
    EXPECT_DOUBLE_EQ(scans[0].pose.linear()(2, 2), 2.0);
    EXPECT_EQ(scans[0].scanner_position(), Eigen::Vector3d(600000, 800000, 400));
    EXPECT_EQ(scans[0].grid->rows, 2u);
    EXPECT_EQ(scans[1].grid->columns, 4u);
    EXPECT_EQ(scans[0].source, (data / "multiple-and-transform.ptx").string() + "#1");
    EXPECT_EQ(scans[1].source, (data / "multiple-and-transform.ptx").string() + "#2");
}

TEST(PtxReader, ComplexTransformKeepsFourOfTwelveCellsInTheirGridPlaces) {
    const auto scans = read_ptx(data / "complex-transform.ptx");
    ASSERT_EQ(scans.size(), 1u);
    const Scan& s = scans[0];
    ASSERT_EQ(s.size(), 4u);
    EXPECT_EQ(s.grid->cells(), 12u);
    EXPECT_EQ(s.grid->rows, 6u);
    EXPECT_EQ(s.grid->columns, 2u);
    // Cells 4..7 of 12, column by column with 6 rows: (row 4, col 0) .. (row 1, col 1).
    EXPECT_EQ(s.grid->row, (std::vector<std::uint32_t>{4, 5, 0, 1}));
    EXPECT_EQ(s.grid->column, (std::vector<std::uint32_t>{0, 0, 1, 1}));
    // [x y z 1]·M worked out by hand for the first and last valid lines.
    EXPECT_NEAR(s.xyz[0].x(), -3.034407381, 1e-9);
    EXPECT_NEAR(s.xyz[0].y(), -3.173781036, 1e-9);
    EXPECT_NEAR(s.xyz[0].z(), -1.823750042, 1e-9);
    EXPECT_NEAR(s.xyz[3].x(), -3.034359790, 1e-9);
    EXPECT_NEAR(s.xyz[3].y(), -3.171403932, 1e-9);
    EXPECT_NEAR(s.xyz[3].z(), -1.822068350, 1e-9);
    ASSERT_EQ(s.rgb.size(), 4u);
    EXPECT_EQ(s.rgb[0], (tlsmon::Rgb8{33, 38, 24}));
    EXPECT_FLOAT_EQ(s.intensity[1], 0.489845f);
}

TEST(PtxReader, PumpScanHas155201PointsOf345By1074Cells) {
    const auto scans = tlsmon::read_scans(data / "pumpA_from_e57.ptx");
    ASSERT_EQ(scans.size(), 1u);
    const Scan& s = scans[0];
    EXPECT_EQ(s.size(), 155201u);
    EXPECT_EQ(s.grid->columns, 345u);
    EXPECT_EQ(s.grid->rows, 1074u);
    EXPECT_EQ(s.grid->cells(), 370530u);
    EXPECT_EQ(s.grid->row.size(), s.size());
    EXPECT_EQ(s.rgb.size(), s.size());
    double near = 1e9, far = 0;
    for (const auto& p : s.xyz) {
        near = std::min(near, (p - s.scanner_position()).norm());
        far = std::max(far, (p - s.scanner_position()).norm());
    }
    EXPECT_NEAR(near, 1.98, 0.005);
    EXPECT_NEAR(far, 5.43, 0.005);
    const auto [lo, hi] = std::minmax_element(s.intensity.begin(), s.intensity.end());
    EXPECT_NEAR(*lo, 0.384, 0.001);
    EXPECT_NEAR(*hi, 0.698, 0.001);
    EXPECT_LT(s.grid->row.back(), 1074u);
    EXPECT_LT(s.grid->column.back(), 345u);
    EXPECT_GT(s.grid->column.back(), s.grid->column.front());
}

TEST_F(PtxBroken, IntegerIntensitiesAreNormalisedWithTheirRawScale) {
    const auto scans = read_ptx(write("int.ptx",
                                      "3\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                      "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
                                      "1 2 3 -2047\n4 5 6 0\n7 8 9 2048\n"));
    const Scan& s = scans[0];
    ASSERT_EQ(s.intensity.size(), 3u);
    EXPECT_EQ(s.intensity_raw_min, -2047.0);
    EXPECT_EQ(s.intensity_raw_max, 2048.0);
    EXPECT_FLOAT_EQ(s.intensity[0], 0.0f);
    EXPECT_NEAR(s.intensity[1], 2047.0 / 4095.0, 1e-6);
    EXPECT_FLOAT_EQ(s.intensity[2], 1.0f);
}

TEST_F(PtxBroken, TenColumnLinesAndCrlfAreRead) {
    const auto scans = read_ptx(write("ten.ptx",
                                      "1\r\n2\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n0 0 1\r\n"
                                      "1 0 0 0\r\n0 1 0 0\r\n0 0 1 0\r\n10 20 30 1\r\n"
                                      "1 2 3 0.25 10 20 30 0 0 1\r\n"
                                      "0 0 0 0.5 0 0 0 0 0 0\r\n"));
    const Scan& s = scans[0];
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s.xyz[0], Eigen::Vector3d(11, 22, 33));
    EXPECT_EQ(s.rgb[0], (tlsmon::Rgb8{10, 20, 30}));
    EXPECT_FLOAT_EQ(s.intensity[0], 0.25f);
    EXPECT_EQ(s.grid->cells(), 2u);
}

TEST_F(PtxBroken, AScanOfOnlyEmptyCellsHasNoPointsButItsGrid) {
    const auto scans = read_ptx(write("empty-cells.ptx",
                                      "2\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                      "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"
                                      "0 0 0 0.5\n0 0 0 0.5\n"));
    EXPECT_EQ(scans[0].size(), 0u);
    EXPECT_EQ(scans[0].grid->cells(), 2u);
}

TEST_F(PtxBroken, WrongCountsAreRejectedAtTheirLine) {
    // 16 declared columns, 15 point lines: the file ends on line 25.
    expect_rejected(write("more.ptx", no_color_with_line(1, "16")), 25,
                    "file ends after 15 of the 16 point lines");
    // 14 declared columns: the 15th point line (line 25) is read as the next header.
    expect_rejected(write("fewer.ptx", no_color_with_line(1, "14")), 25,
                    "expected the column count");
    expect_rejected(write("zero.ptx", no_color_with_line(2, "0")), 2, "no cells");
    expect_rejected(write("neg.ptx", no_color_with_line(2, "-1")), 2, "row count");
    expect_rejected(write("short-matrix.ptx", no_color_with_line(9, "0 0 1")), 9,
                    "expected 4 numbers");
    expect_rejected(write("not-affine.ptx", no_color_with_line(9, "0 0 1 0.5")), 9, "affine");
    expect_rejected(write("three.ptx", no_color_with_line(11, "1 2 3")), 11, "4, 7 or 10 values");
    expect_rejected(write("mixed.ptx", no_color_with_line(13, "1 2 3 0.5 1 2 3")), 13,
                    "earlier lines");
}

// A corrupt matrix was read into points at 1e300 m and rejected only later, by the
// registration, as "too few targets": the reader refuses it, naming what is wrong.
TEST_F(PtxBroken, CorruptTransformationsAreRefusedByTheReader) {
    expect_rejected(write("huge-rotation.ptx", no_color_with_line(7, "1e300 0 0 0")), 10,
                    "rotation part scales by 1 to 1e+300");
    expect_rejected(write("flat.ptx", no_color_with_line(9, "0 0 0 0")), 10,
                    "rotation part scales by 0");
    // A translation of 1e300: every point beyond any coordinate on Earth.
    const fs::path far = write("far.ptx", no_color_with_line(10, "1e300 0 0 1"));
    try {
        tlsmon::read_scans(far);
        ADD_FAILURE() << "read";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("scan 1, point 1 lies at (1"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("beyond 1e8 m"), std::string::npos) << e.what();
    }
    // PDAL's file with a z scale of 2 is still read (a scaled rotation is allowed).
    EXPECT_EQ(tlsmon::read_scans(data / "multiple-and-transform.ptx").size(), 2u);
}

// Operator defect 12: scan 1 has no previous header, so its error must not blame one; the
// hint about too many point lines belongs to the second and later scans only.
TEST_F(PtxBroken, FirstScanErrorDoesNotMentionAPreviousHeader) {
    const fs::path first = write("first.ptx", "hello world\n");
    const std::string m = error_of(first);
    EXPECT_NE(m.find("expected the column count that starts scan 1, found 'hello world'"),
              std::string::npos)
        << m;
    EXPECT_EQ(m.find("previous"), std::string::npos) << m;
    // The 15th of 14 declared lines is read as the header of scan 2: that hint is kept.
    const std::string second = error_of(write("second.ptx", no_color_with_line(1, "14")));
    EXPECT_NE(second.find("starts scan 2"), std::string::npos) << second;
    EXPECT_NE(second.find("more point lines than the previous header's columns × rows"),
              std::string::npos)
        << second;
}

TEST_F(PtxBroken, NonNumbersAndNonFiniteValuesAreRejectedAtTheirLine) {
    expect_rejected(write("nan.ptx", no_color_with_line(14, "nan 1 2 0.5")), 14, "non-finite");
    expect_rejected(write("inf.ptx", no_color_with_line(15, "1 -inf 2 0.5")), 15, "non-finite");
    expect_rejected(write("word.ptx", no_color_with_line(16, "1 2 3 bright")), 16, "not a number");
    expect_rejected(write("glued.ptx", no_color_with_line(17, "1 2 3x 0.5")), 17, "not a number");
    expect_rejected(write("huge.ptx", no_color_with_line(18, "1e999 2 3 0.5")), 18, "out of range");
    expect_rejected(write("intensity.ptx", no_color_with_line(19, "1 2 3 9000")), 19, "intensity");
    expect_rejected(write("colour.ptx",
                          "1\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                          "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 2 3 0.5 256 0 0\n"),
                    11, "colour");
}

TEST_F(PtxBroken, AbsurdDeclaredSizesAreRejectedBeforeAllocating) {
    expect_rejected(write("absurd.ptx", no_color_with_line(1, "4000000000")), 2, "cells but only");
    expect_rejected(write("overflow.ptx", no_color_with_line(1, "99999999999999999999")), 1,
                    "column count");
    expect_rejected(write("wide.ptx", no_color_with_line(1, "5000000000")), 2, "absurd");
}

TEST_F(PtxBroken, EmptyGarbageAndBinaryFilesAreRejected) {
    EXPECT_THROW(read_ptx(write("empty.ptx", "")), FormatError);
    EXPECT_THROW(read_ptx(write("blank.ptx", "\n \n\t\n")), FormatError);
    expect_rejected(write("text.ptx", "hello world\n"), 1, "column count");
    std::mt19937 rng(7);
    std::string garbage(4096, '\0');
    for (char& c : garbage) c = static_cast<char>(rng() & 0xff);
    garbage[0] = '\x01';  // never a digit or white space
    expect_rejected(write("garbage.ptx", garbage), 1, "column count");
    expect_rejected(write("nul.ptx", no_color_with_line(12, std::string("1 2 \0 0.5", 9))), 12,
                    "not a number");
}

TEST_F(PtxBroken, EveryTruncationOfARealFileIsRejectedOrComplete) {
    const std::string full = tlsmon::test::read_file(data / "complex-transform.ptx");
    const std::size_t last_line = full.rfind('\n') + 1;
    for (std::size_t n = 0; n < full.size(); ++n) {
        const fs::path p = write("cut.ptx", full.substr(0, n));
        if (n < last_line) {
            try {
                read_ptx(p);
                ADD_FAILURE() << "prefix of " << n << " bytes accepted";
            } catch (const FormatError& e) {
                EXPECT_EQ(std::string(e.what()).rfind(p.string() + ":", 0), 0u) << e.what();
            }
        } else {
            // Only the last (empty) cell is cut: what is left of it still reads as empty
            // or as too short a line; the four points are never lost silently.
            try {
                EXPECT_EQ(read_ptx(p)[0].size(), 4u);
            } catch (const FormatError&) {
            }
        }
    }
}

TEST_F(PtxBroken, FlippedBytesNeverCrashAndErrorsNameTheFile) {
    const std::string full = tlsmon::test::read_file(data / "complex-transform.ptx");
    std::mt19937 rng(42);
    int rejected = 0;
    for (int k = 0; k < 400; ++k) {
        std::string s = full;
        const std::size_t at = rng() % s.size();
        s[at] = static_cast<char>(s[at] ^ (1 << (rng() % 8)));
        const fs::path p = write("flip.ptx", s);
        try {
            const auto scans = read_ptx(p);
            for (const Scan& scan : scans) {
                EXPECT_EQ(scan.grid->row.size(), scan.size());
                for (const auto& x : scan.xyz) EXPECT_TRUE(x.allFinite());
            }
        } catch (const FormatError& e) {
            ++rejected;
            EXPECT_EQ(std::string(e.what()).rfind(p.string() + ":", 0), 0u) << e.what();
        }
    }
    EXPECT_GT(rejected, 100);  // most single-bit flips break a number or a count
}
