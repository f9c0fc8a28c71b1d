// Zones as boxes, prisms and bands, and the [m3c2] section: what the file says, what the
// stage receives (pipeline_config), and each mistake named by file, line and key.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/config_text.hpp"

namespace tlsmon {
namespace {

using test::error_of;
using test::parse;

const char* kFace = R"(
[[zone]]
name = "south"
min = [2, 44.5, 0]
max = [17, 45.5, 40]

[[zone]]
name = "cap"
polygon = [[2, 45], [17, 45], [9.5, 52]]
z = [38, 41]

[[zone_bands]]
zone = "south"
height = 15
)";

TEST(ConfigZones, BoxPrismAndBandsBecomeNamedZones) {
    const Config c = parse(kFace);
    std::vector<std::string> names;
    for (const auto& z : c.zones) names.push_back(z.name);
    EXPECT_EQ(names, (std::vector<std::string>{"south", "cap", "south 0–15 m", "south 15–30 m",
                                               "south 30–40 m"}));
    // The prism's bounds, and a band's cut of its zone along z.
    EXPECT_EQ(c.zones[1].min, (std::array<double, 3>{2, 45, 38}));
    EXPECT_EQ(c.zones[1].max, (std::array<double, 3>{17, 52, 41}));
    EXPECT_EQ(c.zones[3].min, (std::array<double, 3>{2, 44.5, 15}));
    EXPECT_EQ(c.zones[3].max, (std::array<double, 3>{17, 45.5, 30}));
    EXPECT_EQ(c.zones[3].band_of, "south");

    const PipelineConfig p = pipeline_config(c);
    ASSERT_EQ(p.m3c2.zones.size(), 5u);
    const ZoneShape& cap = p.m3c2.zones[1];
    EXPECT_TRUE(cap.contains({9.5, 48, 40}));
    EXPECT_FALSE(cap.contains({3, 51, 40}));  // inside the bounds, outside the triangle
    EXPECT_FALSE(cap.contains({9.5, 48, 42}));
    EXPECT_TRUE(p.m3c2.zones[3].contains({5, 45, 15}));  // a band's boundary is inside
    EXPECT_FALSE(p.m3c2.zones[3].contains({5, 45, 31}));
    // The registration's σ is taken at each zone's bounding box.
    ASSERT_EQ(p.registration.zones.size(), 5u);
    EXPECT_EQ(p.registration.zones[4].box.min(), Eigen::Vector3d(2, 44.5, 30));
}

TEST(ConfigZones, BandsAlongXFromAGivenStart) {
    const Config c = parse(std::string(kFace) + R"(
[[zone_bands]]
zone = "cap"
axis = "x"
height = 5
from = 7
to = 17
)");
    ASSERT_EQ(c.zones.size(), 7u);
    EXPECT_EQ(c.zones[5].name, "cap 7–12 m");
    EXPECT_EQ(c.zones[6].name, "cap 12–17 m");
    EXPECT_EQ(c.zones[6].polygon.size(), 3u);  // a band of a prism keeps its outline
}

// A zone's design normal: unit length in the zone and its bands, on to the stage's shapes;
// zones whose normals differ may meet but not overlap.
TEST(ConfigZones, DesignNormalsReachTheStageAndMustNotOverlap) {
    const Config c = parse(R"(
[[zone]]
name = "south"
min = [2, 44.5, 0]
max = [17, 45.5, 40]
normal = [0, -2, 0]

[[zone]]
name = "west"
min = [1.5, 45.5, 0]
max = [2.5, 52, 40]
normal = [-1, 0, 0]

[[zone]]
name = "top"
min = [2, 44.5, 30]
max = [17, 45.5, 40]

[[zone_bands]]
zone = "south"
height = 20
)");
    ASSERT_EQ(c.zones.size(), 5u);
    EXPECT_EQ(c.zones[0].normal, (std::array<double, 3>{0, -1, 0}));
    EXPECT_FALSE(c.zones[2].normal.has_value());
    EXPECT_EQ(c.zones[4].normal, (std::array<double, 3>{0, -1, 0}));  // "south 20–40 m"
    const PipelineConfig p = pipeline_config(c);
    EXPECT_EQ(p.m3c2.zones[1].normal, Eigen::Vector3d(-1, 0, 0));
    EXPECT_FALSE(p.m3c2.zones[2].normal.allFinite());
    EXPECT_EQ(p.m3c2.zones[3].normal, Eigen::Vector3d(0, -1, 0));
    EXPECT_EQ(c.m3c2.max_roughness, 0.02);

    const std::string overlap = error_of(R"(
[[zone]]
name = "south"
min = [2, 44.5, 0]
max = [17, 45.5, 40]
normal = [0, -1, 0]

[[zone]]
name = "west"
min = [1.5, 45, 0]
max = [2.5, 52, 40]
normal = [-1, 0, 0]
)");
    EXPECT_NE(overlap.find("site.toml:12:10: key 'zone[1].normal': zone 'west' overlaps zone "
                           "'south', whose normal differs"),
              std::string::npos)
        << overlap;
    EXPECT_NE(
        error_of("[[zone]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nnormal = [0, 0, 0]\n")
            .find("key 'zone[0].normal': expected three numbers [x, y, z], not all zero"),
        std::string::npos);
    EXPECT_NE(error_of("[m3c2]\nmax_roughness = 0\n").find("m3c2.max_roughness"),
              std::string::npos);
}

// A check zone on ground known not to move: marked, inherited by its bands, and its box
// left out of the ICP's stable regions, so that the datum never holds it still.
TEST(ConfigZones, NoChangeZonesLeaveTheStableRegions) {
    const Config c = parse(R"(
[[zone]]
name = "abutment check"
min = [22.6, 55.7, 0.6]
max = [29.4, 56.3, 1.9]
no_change = true

[[zone]]
name = "south"
min = [2, 44.5, 0]
max = [17, 45.5, 40]

[[zone_bands]]
zone = "abutment check"
axis = "x"
height = 4

[[stable_region]]
name = "abutment"
min = [20, 54, -1]
max = [32, 64, 3]
)");
    ASSERT_EQ(c.zones.size(), 4u);
    EXPECT_TRUE(c.zones[0].no_change);
    EXPECT_FALSE(c.zones[1].no_change);
    EXPECT_TRUE(c.zones[2].no_change);  // "abutment check 22.6–26.6 m"
    EXPECT_EQ(c.zones[2].band_of, "abutment check");
    ASSERT_EQ(c.icp.excluded.size(), 1u);  // the zone; its bands lie inside it
    EXPECT_EQ(c.icp.excluded[0].name, "abutment check");
    EXPECT_EQ(c.icp.excluded[0].min, Eigen::Vector3d(22.6, 55.7, 0.6));
    EXPECT_EQ(c.icp.excluded[0].max, Eigen::Vector3d(29.4, 56.3, 1.9));
    EXPECT_EQ(pipeline_config(c).registration.icp.excluded.size(), 1u);
    bool described = false;
    for (const auto& line : describe(c))
        described = described || line.find("no_change = true") != std::string::npos;
    EXPECT_TRUE(described);
    EXPECT_NE(error_of("[[zone]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
                       "no_change = \"yes\"\n")
                  .find("key 'zone[0].no_change'"),
              std::string::npos);
}

TEST(ConfigZones, M3c2SectionDefaultsAndValues) {
    const Config d = parse("");
    EXPECT_TRUE(d.m3c2.enabled);
    EXPECT_TRUE(d.m3c2.orient_to_scanner);
    const Config c = parse(R"(
[m3c2]
core_spacing = 0.25
normal_radii = [0.2, 0.4, 0.8]
orientation = [0, -1, 0]
statistic = "median"
min_points = 20
)");
    EXPECT_EQ(c.m3c2.core_spacing, 0.25);
    EXPECT_EQ(c.m3c2.normal_radii, (std::vector<double>{0.2, 0.4, 0.8}));
    EXPECT_FALSE(c.m3c2.orient_to_scanner);
    EXPECT_EQ(c.m3c2.orientation, Eigen::Vector3d(0, -1, 0));
    EXPECT_EQ(c.m3c2.statistic, m3c2::CylinderStatistic::median);
    EXPECT_EQ(c.m3c2.min_points, 20);
}

TEST(ConfigZones, MistakesNameTheKey) {
    EXPECT_NE(error_of("[[zone]]\nname = \"a\"\npolygon = [[0, 0], [1, 0]]\nz = [0, 1]\n")
                  .find("site.toml:3:11: key 'zone[0].polygon': expected at least 3 vertices"),
              std::string::npos);
    EXPECT_NE(error_of("[[zone]]\nname = \"a\"\npolygon = [[0, 0], [1, 0], [2, 0]]\nz = [0, 1]\n")
                  .find("the polygon has no area"),
              std::string::npos);
    EXPECT_NE(error_of("[[zone]]\nname = \"a\"\npolygon = [[0, 0], [1, 0], [0, 1]]\n")
                  .find("a prism [[zone]] needs z = [z_min, z_max]"),
              std::string::npos);
    EXPECT_NE(error_of("[[zone_bands]]\nzone = \"nowhere\"\nheight = 10\n")
                  .find("key 'zone_bands[0].zone': no [[zone]] named 'nowhere'"),
              std::string::npos);
    EXPECT_NE(error_of(std::string(kFace) + "[[zone_bands]]\nzone = \"south\"\nheight = 15\n")
                  .find("zone 'south 0–15 m' is defined twice"),
              std::string::npos);
    EXPECT_NE(error_of("[m3c2]\norientation = \"sky\"\n")
                  .find("key 'm3c2.orientation': expected \"scanner\" or [x, y, z]"),
              std::string::npos);
    EXPECT_NE(error_of("[m3c2]\norientation = [0, 0, 0]\n").find("must not be zero"),
              std::string::npos);
    EXPECT_NE(error_of("[m3c2]\nnormal_radii = []\n").find("expected 1 to 10 radii"),
              std::string::npos);
    EXPECT_NE(error_of("[m3c2]\nnormal_radii = [0.5, 0.5]\n").find("a radius is listed twice"),
              std::string::npos);
    EXPECT_NE(error_of("[m3c2]\nstatistic = \"mode\"\n").find("'mode' is not one of: mean, median"),
              std::string::npos);
}

}  // namespace
}  // namespace tlsmon
