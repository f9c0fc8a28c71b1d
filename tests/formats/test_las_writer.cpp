// The LAS 1.4 writer against the reader: quantisation, every attribute type with its no-value,
// the WKT and GPS time records, and what it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "formats/las_reader.hpp"
#include "formats/las_writer.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(LasQuantisation, MicrometresAroundTheCentreAndCoarserOnlyWhereTheIntegersWouldOverflow) {
    // UTM-sized coordinates over 30 m: the offset is the box's centre to the metre, 1 µm steps.
    const auto utm = las_quantisation({{512300.2, 5432100.7, 240.0}, {512330.9, 5432110.1, 270.4}});
    EXPECT_EQ(utm.offset, Eigen::Vector3d(512316, 5432105, 255));
    EXPECT_EQ(utm.scale, Eigen::Vector3d::Constant(1e-6));
    // 2 × 2147 m is the most a 32-bit integer spans at 1 µm; 10 km along x needs 10 µm.
    const auto wide = las_quantisation({{0, 0, 0}, {10000, 4000, 4300}});
    EXPECT_DOUBLE_EQ(wide.scale.x(), 1e-5);
    EXPECT_DOUBLE_EQ(wide.scale.y(), 1e-6);
    EXPECT_DOUBLE_EQ(wide.scale.z(), 1e-5);
}

TEST(LasWriter, EveryAttributeTypeTheWktAndTheTimeReadBack) {
    TempDir dir("las-writer");
    LasPoints p;
    p.xyz = {{512300.1234567, 5432100.7654321, 240.5},
             {512330.9, 5432110.1, 270.4},
             {512310, 5432105, 250}};
    p.attributes = {
        {"flag", "0 or 1", LasAttribute::Type::u8, {0, 1, 1}},
        {"count", "points", LasAttribute::Type::u32, {0, 4294967295.0, 17}},
        {"segment", "-1: none", LasAttribute::Type::i32, {-1, 2147483647.0, -2147483648.0}},
        {"distance_m", "float32, NaN: none", LasAttribute::Type::f32, {0.004, kNaN, -1e-7}},
        {"length_m", "float64", LasAttribute::Type::f64, {0.1234567890123, 1e300, kNaN}},
    };
    p.wkt = "PROJCS[\"ETRS89 / UTM zone 32N\"]";
    p.acquired_utc = 1'780'000'000.0;
    const auto file = dir.path() / "points.las";
    write_las(file, p);

    const LasPoints r = read_las_points(file);
    ASSERT_EQ(r.xyz.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k)
        EXPECT_LE((r.xyz[k] - p.xyz[k]).cwiseAbs().maxCoeff(), 0.5e-6 + 1e-9) << k;
    ASSERT_EQ(r.attributes.size(), p.attributes.size());
    for (std::size_t a = 0; a < p.attributes.size(); ++a) {
        SCOPED_TRACE(p.attributes[a].name);
        EXPECT_EQ(r.attributes[a].name, p.attributes[a].name);
        EXPECT_EQ(r.attributes[a].description, p.attributes[a].description);
        EXPECT_EQ(r.attributes[a].type, p.attributes[a].type);
        for (std::size_t k = 0; k < 3; ++k) {
            double expected = p.attributes[a].values[k];
            if (p.attributes[a].type == LasAttribute::Type::f32)
                expected = static_cast<float>(expected);
            const double got = r.attributes[a].values[k];
            EXPECT_TRUE(got == expected || (std::isnan(got) && std::isnan(expected)))
                << k << ": " << got << " vs " << expected;
        }
    }
    EXPECT_EQ(r.wkt, p.wkt);
    ASSERT_TRUE(r.acquired_utc);
    EXPECT_NEAR(*r.acquired_utc, *p.acquired_utc, 1e-3);
    // A scan reader sees the same points (the extra bytes skipped).
    const auto scans = read_las(file);
    ASSERT_EQ(scans.size(), 1u);
    EXPECT_EQ(scans[0].xyz, r.xyz);
    EXPECT_FALSE(std::filesystem::exists(file.string() + ".part"));
}

TEST(LasWriter, RefusesWhatLasCannotHoldAndLeavesNoFile) {
    TempDir dir("las-writer-refusals");
    const auto file = dir.path() / "x.las";
    const auto refused = [&](const LasAttribute& a, const std::string& says) {
        LasPoints p;
        p.xyz = {{0, 0, 0}, {1, 1, 1}};
        p.attributes = {a};
        try {
            write_las(file, p);
            ADD_FAILURE() << a.name << ": written";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
        EXPECT_FALSE(std::filesystem::exists(file));
    };
    refused({"short", "", LasAttribute::Type::f32, {1}}, "has 1 values for 2 points");
    refused({std::string(33, 'n'), "", LasAttribute::Type::f32, {1, 2}}, "1 to 32 bytes");
    refused({"d", std::string(33, 'd'), LasAttribute::Type::f32, {1, 2}}, "longer than 32");
    refused({"flag", "", LasAttribute::Type::u8, {0, 256}}, "holds 256");
    refused({"count", "", LasAttribute::Type::u32, {-1, 0}}, "not an integer of its type");
    refused({"segment", "", LasAttribute::Type::i32, {0.5, 0}}, "not an integer of its type");
    refused({"segment", "", LasAttribute::Type::i32, {kNaN, 0}}, "not an integer of its type");
}

}  // namespace
}  // namespace tlsmon::test
