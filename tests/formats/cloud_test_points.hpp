#pragma once
// Known points for the PLY and PCD reader tests: files are written here byte by byte (not
// with PCL or any other writer) and read back through read_scans.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/scan.hpp"
#include "formats/format_error.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test {

// A fixture with a scratch folder for the files a reader test writes.
class CloudFileTest : public ::testing::Test {
  protected:
    std::filesystem::path write(const std::string& name, const std::string& bytes) const {
        return write_file(dir_ / name, bytes);
    }

    TempDir dir_;
};

// Appends v's bytes in the machine's order (little-endian here), or reversed.
template <class T>
void append(std::string& out, T v, bool reversed = false) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (reversed) std::reverse(b, b + sizeof v);
    out.append(b, sizeof v);
}

inline std::string error_of(const std::filesystem::path& p) {
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
inline const std::vector<Point> kPoints = {{637012.24, 849028.31, 431.66, 0.25f, 255, 0, 10},
                                           {-1.5, 2.25, -3.125, 0.5f, 1, 2, 3},
                                           {0.001, 0.002, 0.003, 1.0f, 68, 77, 88}};

inline void expect_known_points(const Scan& scan, double tolerance) {
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

}  // namespace tlsmon::test
