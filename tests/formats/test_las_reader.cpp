// LAS reader on the real files of shared/data/las (INVENTORY.md) and on broken copies.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "formats/format_error.hpp"
#include "formats/las_reader.hpp"
#include "formats/scan_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

const fs::path kLasDir = fs::path(TLSMON_DATA_DIR) / "las";

struct Sample {
    std::size_t index;
    std::array<double, 3> xyz;
};

struct Expected {
    const char* file;
    std::size_t points;
    std::vector<Sample> samples;
    int intensity_min;  // raw LAS values
    int intensity_max;
};

// Expected values were decoded independently of this reader with a throwaway Python script
// (struct.unpack of the LAS 1.4 R15 header and point record layouts, X = Xrecord * scale +
// offset) over each file; samples are the first, middle and last point.
const std::vector<Expected> kExpected = {
    {"laspy/1_4_w_evlr.las",
     1000,
     {{0, {1694510.3869346841, 1816497.966263977, 5598.3596128149675}},
      {500, {1694349.7864932816, 1816494.9662393024, 5597.029578302081}},
      {999, {1694291.6363326558, 1816493.0662305846, 5597.089652537912}}},
     2,
     68},
    {"laspy/autzen.las",
     106,
     {{0, {636083.3, 849398.65, 407.35}},
      {53, {637118.4400000001, 852409.84, 424.08}},
      {105, {637857.41, 853213.98, 424.87}}},
     0,
     238},
    {"laspy/autzen_geo_proj.las",
     106,
     {{0, {636083.3, 849398.65, 407.35}},
      {53, {637118.4400000001, 852409.84, 424.08}},
      {105, {637857.41, 853213.98, 424.87}}},
     0,
     238},
    {"laspy/extrabytes.las",
     1065,
     {{0, {637012.24, 849028.31, 431.66}},
      {532, {636817.75, 852041.27, 461.84000000000003}},
      {1064, {637342.85, 853240.3200000001, 423.92}}},
     0,
     254},
    {"laspy/simple.las",
     1065,
     {{0, {637012.24, 849028.31, 431.66}},
      {532, {636817.75, 852041.27, 461.84000000000003}},
      {1064, {637342.85, 853240.3200000001, 423.92}}},
     0,
     254},
    {"laspy/simple1_1.las",
     1065,
     {{0, {637012.24, 849028.31, 431.66}},
      {532, {636817.75, 852041.27, 461.84000000000003}},
      {1064, {637342.85, 853240.3200000001, 423.92}}},
     0,
     254},
    {"laspy/simple1_4.las",
     22600,
     {{0, {1.0, 1.0, 100.0}},
      {11300, {1.0, 51.000000000000014, 176.0}},
      {22599, {226.00000000000003, 100.00000000000003, 185.0}}},
     0,
     0},
    {"laspy/test1_4.las",
     1000,
     {{0, {1694510.3869346841, 1816497.966263977, 5598.3596128149675}},
      {500, {1694349.7864932816, 1816494.9662393024, 5597.029578302081}},
      {999, {1694291.6363326558, 1816493.0662305846, 5597.089652537912}}},
     2,
     68},
    {"laspy/unregistered_extra_bytes.las",
     4,
     {{0, {1.0, 1.0, 1.0}}, {2, {3.0, 3.0, 3.0}}, {3, {4.0, 4.0, 4.0}}},
     0,
     0},
    {"laz-perf/1815.las",
     1247,
     {{0, {2014125.939479005, 6493002.487217385, 104.82056279588402}},
      {623, {2014435.832999005, 6493541.013997385, 110.573802795884}},
      {1246, {2014990.3331690049, 6493996.282007385, 95.59921279588401}}},
     0,
     50449},
    {"laz-perf/extrabytes.las",
     1065,
     {{0, {637012.24, 849028.31, 431.66}},
      {532, {636817.75, 852041.27, 461.84000000000003}},
      {1064, {637342.85, 853240.3200000001, 423.92}}},
     0,
     254},
    {"laz-perf/no-points-1.3.las", 0, {}, 0, 0},
    {"laz-perf/point-color-time.las",
     1065,
     {{0, {494428.61, 4877455.58, 131.57}},
      {532, {494341.42, 4878371.5600000005, 140.77}},
      {1064, {494490.24, 4878741.67, 129.21}}},
     0,
     254},
    {"laz-perf/point-time.las",
     1065,
     {{0, {494428.61, 4877455.58, 131.57}},
      {532, {494341.42, 4878371.5600000005, 140.77}},
      {1064, {494490.24, 4878741.67, 129.21}}},
     0,
     254},
    {"laz-perf/point10-1.0.las", 1, {{0, {1.0, 2.0, 3.0}}}, 42, 42},
    {"laz-perf/point10-1.1.las", 1, {{0, {1.0, 2.0, 3.0}}}, 42, 42},
    {"laz-perf/point10.las",
     1065,
     {{0, {494428.61, 4877455.58, 131.57}},
      {532, {494341.42, 4878371.5600000005, 140.77}},
      {1064, {494490.24, 4878741.67, 129.21}}},
     0,
     254},
    {"libLAS/1.0_0.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.0_1.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.1_0.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.1_1.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.2-with-color.las",
     1065,
     {{0, {637012.24, 849028.31, 431.66}},
      {532, {636817.75, 852041.27, 461.84000000000003}},
      {1064, {637342.85, 853240.3200000001, 423.92}}},
     0,
     254},
    {"libLAS/1.2_0.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.2_1.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.2_2.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/1.2_3.las", 1, {{0, {470692.44, 4602888.9, 16.0}}}, 0, 0},
    {"libLAS/TO_core_last_clip.las",
     8,
     {{0, {630262.3, 4834500.0, 51.53}},
      {4, {630327.59, 4834500.0, 54.730000000000004}},
      {7, {630280.89, 4834500.0, 51.620000000000005}}},
     90,
     670},
    {"libLAS/autzen.las",
     106,
     {{0, {636083.3, 849398.65, 407.35}},
      {53, {637118.4400000001, 852409.84, 424.08}},
      {105, {637857.41, 853213.98, 424.87}}},
     0,
     238},
    {"libLAS/bad_points_1.1.las", 1, {{0, {0.0, 0.0, 0.0}}}, 0, 0},
    {"libLAS/lots_of_vlr.las", 1, {{0, {715001.346, 839349.171, 17.275000000000002}}}, 105, 105},
    {"libLAS/srs.las",
     10,
     {{0, {289814.15, 4320978.61, 170.76}},
      {5, {289816.56, 4320979.71, 170.66}},
      {9, {289818.5, 4320980.59, 170.58}}},
     240,
     280},
    {"libLAS/srs_utm17.las",
     10,
     {{0, {289814.15, 4320978.61, 170.76}},
      {5, {289816.56, 4320979.71, 170.66}},
      {9, {289818.5, 4320980.59, 170.58}}},
     240,
     280},
    {"libLAS/srs_vertcs.las",
     10,
     {{0, {289814.15, 4320978.61, 170.76}},
      {5, {289816.56, 4320979.71, 170.66}},
      {9, {289818.5, 4320980.59, 170.58}}},
     240,
     280},
    {"more/certainty3d-color-utm-feet-navd88.las",
     10126,
     {{0, {6327733.851294488, 2069937.310141398, 2848.2016427022377}},
      {5063, {6329285.87284011, 2068634.948412256, 2848.011354326168}},
      {10125, {6327779.513023613, 2070486.319247068, 2801.420240098068}}},
     56,
     2505},
    {"more/file_with_both_wkt_and_geotiff_vlrs.las",
     25408,
     {{0, {2445180.75, 604324.04, 1354.22}},
      {12704, {2445208.29, 604331.57, 1354.28}},
      {25407, {2445180.74, 604301.55, 1365.01}}},
     996,
     57345},
    {"more/simple1_3.las",
     999,
     {{0, {-234935.84100000001, 5800843.145, 265.094}},
      {499, {-235263.823, 5800911.155, 271.889}},
      {998, {-235433.76, 5800946.08, 273.729}}},
     0,
     220},
    {"more/vegetation_1_3.las",
     10683,
     {{0, {-98449.688, -55970.553, -81458.594}},
      {5341, {-98448.561, -55970.659, -81459.279}},
      {10682, {-98447.745, -55974.739, -81456.955}}},
     0,
     37522},
};

std::vector<fs::path> files_with_extension(const std::string& ext) {
    std::vector<fs::path> out;
    for (const auto& entry : fs::recursive_directory_iterator(kLasDir)) {
        if (entry.is_regular_file() && entry.path().extension() == ext) {
            out.push_back(entry.path());
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The message of the FormatError that parsing `bytes` throws, or "" when it does not throw.
std::string error_of(const std::string& bytes, const std::string& name = "broken.las") {
    try {
        parse_las(bytes.data(), bytes.size(), name);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

template <class T>
void store(std::string& bytes, std::size_t at, T value) {
    std::memcpy(bytes.data() + at, &value, sizeof value);
}

TEST(LasReader, EveryLasFileInTheDataFolderIsListed) {
    std::set<std::string> listed;
    for (const auto& e : kExpected) listed.insert(e.file);
    const auto files = files_with_extension(".las");
    ASSERT_EQ(files.size(), kExpected.size());
    for (const auto& f : files) {
        EXPECT_TRUE(listed.count(fs::relative(f, kLasDir).string())) << f;
    }
}

TEST(LasReader, EveryFileGivesItsPointCountCoordinatesAndIntensityRange) {
    for (const auto& e : kExpected) {
        SCOPED_TRACE(e.file);
        const fs::path path = kLasDir / e.file;
        const std::vector<Scan> scans = read_scans(path);
        ASSERT_EQ(scans.size(), 1u);
        const Scan& scan = scans[0];
        EXPECT_EQ(scan.source, path.string());
        ASSERT_EQ(scan.size(), e.points);
        for (const auto& s : e.samples) {
            for (int k = 0; k < 3; ++k) {
                EXPECT_NEAR(scan.xyz[s.index][k], s.xyz[k], 1e-6) << "point " << s.index;
            }
        }
        ASSERT_EQ(scan.intensity.size(), e.points);
        if (e.points == 0) continue;
        const auto [lo, hi] = std::minmax_element(scan.intensity.begin(), scan.intensity.end());
        const double span = scan.intensity_raw_max - scan.intensity_raw_min;
        EXPECT_EQ(std::lround(scan.intensity_raw_min + *lo * span), e.intensity_min);
        EXPECT_EQ(std::lround(scan.intensity_raw_min + *hi * span), e.intensity_max);
        // The spec's fixed 16-bit scale, whatever range the file happens to use.
        EXPECT_EQ(scan.intensity_raw_max, 65535.0);
        EXPECT_GE(*lo, 0.0f);
        EXPECT_LE(*hi, 1.0f);
    }
}

TEST(LasReader, ColourIsKeptOrScaledFromSixteenBits) {
    // simple.las stores 8-bit colour in the 16-bit fields: first point (68, 77, 88).
    const Scan simple = read_las(kLasDir / "laspy/simple.las").at(0);
    ASSERT_EQ(simple.rgb.size(), 1065u);
    EXPECT_EQ(simple.rgb[0], (Rgb8{68, 77, 88}));
    EXPECT_EQ(simple.rgb[1064], (Rgb8{138, 107, 136}));
    // certainty3d: real 16-bit colour, first point (36096, 32256, 24832) -> high bytes.
    const Scan c3d = read_las(kLasDir / "more/certainty3d-color-utm-feet-navd88.las").at(0);
    ASSERT_EQ(c3d.rgb.size(), 10126u);
    EXPECT_EQ(c3d.rgb[0], (Rgb8{141, 126, 97}));
    // simple1_4 (format 7): (25600, 26624, 26880) -> (100, 104, 105).
    const Scan pf7 = read_las(kLasDir / "laspy/simple1_4.las").at(0);
    EXPECT_EQ(pf7.rgb[0], (Rgb8{100, 104, 105}));
    // libLAS 1.2_2 (format 2, no GPS time): (255, 12, 234).
    EXPECT_EQ(read_las(kLasDir / "libLAS/1.2_2.las").at(0).rgb.at(0), (Rgb8{255, 12, 234}));
    // Formats without colour give none.
    EXPECT_TRUE(read_las(kLasDir / "laspy/test1_4.las").at(0).rgb.empty());
}

TEST(LasReader, ExtraBytesAreSkipped) {
    // 61-byte records (format 3 + 27 extra bytes) with and without the 1.4 header hold the
    // same points as the 34-byte records of simple.las.
    const Scan plain = read_las(kLasDir / "laspy/simple.las").at(0);
    for (const char* f : {"laspy/extrabytes.las", "laz-perf/extrabytes.las"}) {
        SCOPED_TRACE(f);
        const Scan extra = read_las(kLasDir / f).at(0);
        ASSERT_EQ(extra.size(), plain.size());
        for (std::size_t i = 0; i < plain.size(); ++i) {
            ASSERT_EQ(extra.xyz[i], plain.xyz[i]) << "point " << i;
            ASSERT_EQ(extra.intensity[i], plain.intensity[i]) << "point " << i;
            ASSERT_EQ(extra.rgb[i], plain.rgb[i]) << "point " << i;
        }
    }
    // Format 6 records of 34 bytes without an extra-bytes VLR: (1,1,1) .. (4,4,4).
    const Scan unregistered = read_las(kLasDir / "laspy/unregistered_extra_bytes.las").at(0);
    ASSERT_EQ(unregistered.size(), 4u);
    EXPECT_EQ(unregistered.xyz[1], Eigen::Vector3d(2, 2, 2));
}

// read_las_points: the extra bytes by their descriptors. laspy's sample repeats each point's
// intensity and colour as extra bytes (an unsigned long "Intensity" and a 3-element array of
// doubles "Colors", the deprecated array types of LAS 1.4 R13), so the base record checks them.
TEST(LasReader, ExtraBytesAreReadByTheirDescriptors) {
    for (const char* f : {"laspy/extrabytes.las", "laz-perf/extrabytes.las"}) {
        SCOPED_TRACE(f);
        const Scan scan = read_las(kLasDir / f).at(0);
        const LasPoints points = read_las_points(kLasDir / f);
        ASSERT_EQ(points.xyz, scan.xyz);
        std::vector<std::string> names;
        for (const auto& a : points.attributes) names.push_back(a.name);
        ASSERT_EQ(names, (std::vector<std::string>{"Colors[0]", "Colors[1]", "Colors[2]",
                                                   "Flags[0]", "Flags[1]", "Intensity", "Time"}));
        EXPECT_EQ(points.attributes[5].description, "Brightness");
        EXPECT_EQ(points.attributes[5].type, LasAttribute::Type::u32);
        for (std::size_t i = 0; i < scan.size(); ++i) {
            EXPECT_EQ(points.attributes[5].values[i], std::round(scan.intensity[i] * 65535.0)) << i;
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(points.attributes[std::size_t(c)].values[i], scan.rgb[i][std::size_t(c)])
                    << i;
        }
        EXPECT_TRUE(points.wkt.empty());
    }
    // The OGC WKT record of a LAS 1.4 file that also has GeoTIFF keys.
    const LasPoints wkt = read_las_points(kLasDir / "more/file_with_both_wkt_and_geotiff_vlrs.las");
    EXPECT_EQ(wkt.xyz.size(), 25408u);
    EXPECT_EQ(wkt.wkt.rfind("PROJCS[\"NAD83_2011_Nebraska_ft\"", 0), 0u) << wkt.wkt;
    EXPECT_EQ(wkt.wkt.back(), ']');
}

TEST(LasReader, AdjustedStandardGpsTimeGivesTheAcquisitionTime) {
    // Earliest GPS time + 1e9 s from 1980-01-06, less the leap seconds then in force (16 in
    // May 2014, 18 since 2017), computed with Python's datetime.
    EXPECT_NEAR(read_las(kLasDir / "laspy/test1_4.las").at(0).acquired_utc.value(),
                1399142220.534005 - 16, 1e-5);  // 2014-05-03T18:36:44Z
    EXPECT_NEAR(read_las(kLasDir / "laz-perf/1815.las").at(0).acquired_utc.value(),
                1491014896.0 - 18, 1e-5);  // 2017-04-01T02:47:58Z
    // GPS week time (global encoding bit 0 clear) has no date.
    EXPECT_FALSE(read_las(kLasDir / "laspy/simple.las").at(0).acquired_utc.has_value());
}

TEST(LasReader, EveryCompressedFileGetsTheClearError) {
    const auto laz = files_with_extension(".laz");
    ASSERT_EQ(laz.size(), 19u);
    for (const auto& f : laz) {
        SCOPED_TRACE(f.string());
        try {
            read_scans(f);
            ADD_FAILURE() << "LAZ read without error";
        } catch (const FormatError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(f.string()), std::string::npos) << m;
            EXPECT_NE(m.find("at byte 104"), std::string::npos) << m;
            EXPECT_NE(m.find("compressed LAS (LAZ/COPC) is not supported"), std::string::npos);
        }
    }
}

TEST(LasReader, TruncatedCopiesAreRejectedWithTheByteOffset) {
    const std::string simple = test::read_file(kLasDir / "laspy/simple.las");
    EXPECT_NE(error_of(simple.substr(0, 100)).find("at byte 100: file ends inside the LAS public"),
              std::string::npos);
    EXPECT_NE(error_of(simple.substr(0, 3)).find("at byte 0: not a LAS file"), std::string::npos);
    EXPECT_NE(error_of("").find("at byte 0"), std::string::npos);
    // Cut inside the point records: the error names the point data offset (227).
    const std::string cut = error_of(simple.substr(0, simple.size() - 10));
    EXPECT_NE(cut.find("broken.las: at byte 227: 1065 point records of 34 bytes need 36210 bytes"),
              std::string::npos)
        << cut;
    // Every shorter prefix fails cleanly (no crash, no other exception type).
    for (std::size_t n = 0; n < 2400; n += 7) EXPECT_NE(error_of(simple.substr(0, n)), "") << n;
    // A truncated copy on disk through read_scans names the file.
    const test::TempDir dir;
    const fs::path tmp =
        test::write_file(dir / "truncated_test1_4.las",
                         test::read_file(kLasDir / "laspy/test1_4.las").substr(0, 5000));
    try {
        read_scans(tmp);
        ADD_FAILURE() << "truncated file read";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find(tmp.string() + ": at byte 2305: 1000 point records"),
                  std::string::npos)
            << e.what();
    }
}

TEST(LasReader, HeaderFieldsPointingOutsideTheFileAreRejected) {
    const std::string simple = test::read_file(kLasDir / "laspy/simple.las");    // 1.2, pf 3
    const std::string t14 = test::read_file(kLasDir / "laspy/test1_4.las");      // 1.4, pf 6
    const std::string evlr = test::read_file(kLasDir / "laspy/1_4_w_evlr.las");  // 1 EVLR at 32305
    const std::string autzen = test::read_file(kLasDir / "laspy/autzen.las");    // 4 VLRs
    struct Case {
        const char* what;
        std::string bytes;
        const char* expected;
    };
    std::vector<Case> cases;
    auto edit = [&](const char* what, const std::string& base, auto change, const char* expected) {
        std::string b = base;
        change(b);
        cases.push_back({what, std::move(b), expected});
    };
    edit(
        "point data offset beyond the end", simple,
        [](std::string& b) { store<std::uint32_t>(b, 96, 1u << 30); },
        "at byte 96: offset to point data");
    edit(
        "point data offset inside the header", simple,
        [](std::string& b) { store<std::uint32_t>(b, 96, 100); },
        "at byte 96: offset to point data");
    edit(
        "absurd legacy point count", simple,
        [](std::string& b) { store<std::uint32_t>(b, 107, 0xFFFFFFFFu); },
        "at byte 227: 4294967295 point records");
    edit(
        "absurd 64-bit point count", t14,
        [](std::string& b) { store<std::uint64_t>(b, 247, 1ull << 62); },
        "at byte 2305: 4611686018427387904 point records");
    edit(
        "count times record length overflows", t14,
        [](std::string& b) { store<std::uint64_t>(b, 247, ~0ull); }, "need more bytes");
    edit(
        "record length below the format's", simple,
        [](std::string& b) { store<std::uint16_t>(b, 105, 20); },
        "at byte 105: point record length 20 is smaller than point format 3 needs (34)");
    edit(
        "record length zero", simple, [](std::string& b) { store<std::uint16_t>(b, 105, 0); },
        "at byte 105");
    edit(
        "header size beyond the file", simple,
        [](std::string& b) { store<std::uint16_t>(b, 94, 60000); },
        "at byte 94: header size 60000");
    edit(
        "header size below the version's", t14,
        [](std::string& b) { store<std::uint16_t>(b, 94, 227); },
        "at byte 94: header size 227 is smaller than LAS 1.4 needs (375)");
    edit(
        "VLR length past the point data", autzen,
        [](std::string& b) { store<std::uint16_t>(b, 227 + 20, 0xFFFF); },
        "at byte 247: VLR 1 record length 65535");
    edit(
        "absurd VLR count", autzen,
        [](std::string& b) { store<std::uint32_t>(b, 100, 0xFFFFFFFFu); },
        "does not fit before the point data");
    edit(
        "EVLR start outside the file", evlr,
        [](std::string& b) { store<std::uint64_t>(b, 235, 1ull << 40); },
        "at byte 235: start of the first EVLR");
    edit(
        "EVLR length past the end", evlr,
        [](std::string& b) {
            std::uint64_t start;
            std::memcpy(&start, b.data() + 235, 8);
            store<std::uint64_t>(b, start + 20, 1ull << 40);
        },
        "at byte 32325: EVLR 1 record length 1099511627776 runs past the end");
    edit(
        "unknown point format", simple, [](std::string& b) { b[104] = 11; },
        "at byte 104: unknown point data record format 11");
    edit(
        "zero scale", simple, [](std::string& b) { store<double>(b, 139, 0.0); },
        "at byte 139: scale factor of Y is 0");
    // Corrupt, yet finite: the points would be read far from where they are.
    edit(
        "a scale of a kilometre", simple, [](std::string& b) { store<double>(b, 131, 1000.0); },
        "at byte 131: scale factor of X is 1000");
    edit(
        "an offset of 1e300", simple, [](std::string& b) { store<double>(b, 163, 1e300); },
        "at byte 163: offset of Y is 1e+300, beyond any coordinate on Earth");
    edit(
        "NaN offset", simple,
        [](std::string& b) { store<double>(b, 171, std::numeric_limits<double>::quiet_NaN()); },
        "at byte 171: offset of Z");
    edit(
        "version 2.2", simple, [](std::string& b) { b[24] = 2; },
        "at byte 24: unsupported LAS version 2.2");
    edit(
        "bad signature", simple, [](std::string& b) { b[0] = 'X'; }, "at byte 0: not a LAS file");
    edit(
        "compression bit 0x40", simple, [](std::string& b) { b[104] = char(0x43); },
        "at byte 104: compressed LAS");
    for (const auto& c : cases) {
        const std::string m = error_of(c.bytes);
        EXPECT_EQ(m.rfind("broken.las: ", 0), 0u) << c.what << ": " << m;
        EXPECT_NE(m.find(c.expected), std::string::npos) << c.what << ": " << m;
    }
}

TEST(LasReader, FlippedBytesGiveAScanOrAFormatError) {
    // Random bytes of the header and VLR area of real files replaced: the reader either
    // reads a scan no larger than the file allows or throws FormatError, nothing else.
    std::mt19937 rng(20240521);
    for (const char* f : {"laspy/test1_4.las", "laspy/autzen.las", "more/simple1_3.las",
                          "laz-perf/no-points-1.3.las", "libLAS/1.2_3.las"}) {
        const std::string original = test::read_file(kLasDir / f);
        const std::size_t area = std::min<std::size_t>(original.size(), 2400);
        std::size_t rejected = 0;
        for (int trial = 0; trial < 300; ++trial) {
            std::string b = original;
            for (int k = 0; k < 3; ++k) b[rng() % area] = static_cast<char>(rng());
            try {
                const Scan s = parse_las(b.data(), b.size(), f);
                EXPECT_LE(s.size() * 20, b.size()) << f;
            } catch (const FormatError&) {
                ++rejected;
            }
        }
        SCOPED_TRACE(f);
        EXPECT_GT(rejected, 0u);
    }
}

}  // namespace
}  // namespace tlsmon
