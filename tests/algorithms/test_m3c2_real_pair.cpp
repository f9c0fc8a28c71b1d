// M3C2 on the real pair of ../shared/data/xyz (py4dgeo's test planes, INVENTORY.md): t2 is
// t1 lowered by 0.100 m, so with the normal up every core point measures about -0.100 m.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "algorithms/m3c2/reference.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon::test {
namespace {

using namespace tlsmon::m3c2;

std::vector<Eigen::Vector3d> points_of(const std::filesystem::path& path) {
    std::vector<Eigen::Vector3d> points;
    for (const auto& scan : read_scans(path))
        points.insert(points.end(), scan.xyz.begin(), scan.xyz.end());
    return points;
}

TEST(M3c2RealPair, PlaneLoweredByTenCentimetres) {
    const std::filesystem::path data = TLSMON_DATA_DIR;
    const auto t1 = points_of(data / "xyz/plane_horizontal_t1.xyz");
    const auto t2 = points_of(data / "xyz/plane_horizontal_t2.xyz");
    ASSERT_EQ(t1.size(), 441u);
    ASSERT_EQ(t2.size(), 441u);
    // Every point of t1 a core point; normal radius 2.0, cylinder radius 3.0, half-length 1.0.
    const Reference r = prepare_reference(t1, t1, {{2.0}, Orientation::along({0, 0, 1})},
                                          {3.0, 1.0, CylinderStatistic::mean});
    const auto d = distances(r, cylinder_sides(r.cylinders, t2), {5, 0.0});
    double sum = 0;
    std::size_t valid = 0, significant = 0;
    for (std::size_t k = 0; k < d.size(); ++k) {
        ASSERT_FALSE(std::isnan(d[k].distance)) << k;
        EXPECT_GT(r.normals()[k].z(), 0.99);
        sum += d[k].distance;
        ++valid;
        significant += d[k].significant;
    }
    EXPECT_EQ(valid, 441u);
    EXPECT_NEAR(sum / valid, -0.100, 0.0005);
    EXPECT_EQ(significant, 441u);  // 10 cm against a few millimetres of noise
}

}  // namespace
}  // namespace tlsmon::test
