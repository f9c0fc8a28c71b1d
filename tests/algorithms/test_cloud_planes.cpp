// The planes of an unstructured cloud (algorithms/campaign/cloud_planes.hpp) on a synthetic
// yard: a 20 m × 20 m floor, a 6 × 4 × 5 m block on it (four walls and a roof) and a round
// column of 1.5 m radius, sampled at random with 1 cm noise. Every face of the block and the
// floor must come out as one plane each, on its true plane; the column as none.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "algorithms/campaign/cloud_planes.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {
namespace {

using Eigen::Vector3d;

struct TruePlane {
    Vector3d normal;
    double offset;  // n·x
};

struct Yard {
    std::vector<Vector3d> points;
    std::vector<TruePlane> planes;
    Vector3d column{-5.0, -5.0, 0.0};
    double column_radius = 1.5;
};

Yard yard(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.01);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Yard y;
    const auto add = [&](const Vector3d& corner, const Vector3d& a, const Vector3d& b, int n) {
        for (int k = 0; k < n; ++k)
            y.points.push_back(corner + u(rng) * a + u(rng) * b +
                               Vector3d(noise(rng), noise(rng), noise(rng)));
    };
    // The floor, but not under the block or inside the column.
    for (int k = 0; k < 160000; ++k) {
        const Vector3d p(-10 + 20 * u(rng), -10 + 20 * u(rng), 0.0);
        if (p.x() > 2 && p.x() < 8 && p.y() > 1 && p.y() < 5) continue;
        if ((p - y.column).norm() < y.column_radius) continue;
        y.points.push_back(p + Vector3d(noise(rng), noise(rng), noise(rng)));
    }
    y.planes.push_back({Vector3d::UnitZ(), 0.0});
    // The block: x 2..8, y 1..5, z 0..5.
    add({2, 1, 0}, {6, 0, 0}, {0, 0, 5}, 12000);  // south, y = 1
    add({2, 5, 0}, {6, 0, 0}, {0, 0, 5}, 12000);  // north, y = 5
    add({2, 1, 0}, {0, 4, 0}, {0, 0, 5}, 8000);   // west, x = 2
    add({8, 1, 0}, {0, 4, 0}, {0, 0, 5}, 8000);   // east, x = 8
    add({2, 1, 5}, {6, 0, 0}, {0, 4, 0}, 9600);   // roof, z = 5
    y.planes.push_back({Vector3d::UnitY(), 1.0});
    y.planes.push_back({Vector3d::UnitY(), 5.0});
    y.planes.push_back({Vector3d::UnitX(), 2.0});
    y.planes.push_back({Vector3d::UnitX(), 8.0});
    y.planes.push_back({Vector3d::UnitZ(), 5.0});
    for (int k = 0; k < 30000; ++k) {
        const double phi = 2 * std::numbers::pi * u(rng);
        y.points.push_back(
            y.column +
            Vector3d(y.column_radius * std::cos(phi), y.column_radius * std::sin(phi), 5 * u(rng)) +
            Vector3d(noise(rng), noise(rng), noise(rng)));
    }
    return y;
}

TEST(CloudPlanes, EveryFaceOnceOnItsTruePlaneAndNoneOnTheColumn) {
    const Yard y = yard(3);
    const auto planes = detect_cloud_planes(y.points, {}, 2);
    std::string found_planes;
    for (const auto& p : planes)
        found_planes += "\n  n (" + std::to_string(p.normal.x()) + ", " +
                        std::to_string(p.normal.y()) + ", " + std::to_string(p.normal.z()) +
                        ") d " + std::to_string(p.distance()) + ", " + std::to_string(p.points) +
                        " points, extents " + std::to_string(p.extent_long) + " × " +
                        std::to_string(p.extent_short) + " m";
    ASSERT_EQ(planes.size(), y.planes.size()) << found_planes;
    std::vector<int> found(y.planes.size());
    for (const auto& p : planes) {
        // The true plane it is (either sign): normal within 0.5°, offset within 1 cm.
        int which = -1;
        for (std::size_t k = 0; k < y.planes.size(); ++k) {
            const TruePlane& t = y.planes[k];
            const double sign = p.normal.dot(t.normal) < 0 ? -1.0 : 1.0;
            if (sign * p.normal.dot(t.normal) > std::cos(0.5 * std::numbers::pi / 180) &&
                std::abs(sign * p.distance() - t.offset) < 0.01)
                which = int(k);
        }
        ASSERT_GE(which, 0) << "a plane with normal " << p.normal.transpose() << " at "
                            << p.centroid.transpose() << " is none of the yard's";
        ++found[std::size_t(which)];
        EXPECT_GT(std::hypot(p.centroid.x() - y.column.x(), p.centroid.y() - y.column.y()),
                  y.column_radius + 0.5);
        EXPECT_NEAR(p.residual_sigma, 0.01, 0.003);  // the noise along the normal
    }
    for (std::size_t k = 0; k < found.size(); ++k) EXPECT_EQ(found[k], 1) << "plane " << k;
    // Largest first: the floor.
    EXPECT_GT(std::abs(planes.front().normal.z()), 0.99);
    EXPECT_LT(std::abs(planes.front().distance()), 0.01);
}

TEST(CloudPlanes, TheSameOnOneThreadAsOnTwo) {
    const Yard y = yard(4);
    const auto one = detect_cloud_planes(y.points, {}, 1);
    const auto two = detect_cloud_planes(y.points, {}, 2);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t k = 0; k < one.size(); ++k) {
        EXPECT_EQ(one[k].points, two[k].points);
        EXPECT_EQ(one[k].normal, two[k].normal);
    }
}

TEST(CloudPlanes, BadParametersAreRefused) {
    CloudPlaneParameters p;
    p.radius = 0.05;  // below the spacing
    EXPECT_THROW(validate(p), Error);
    p = {};
    p.max_angle_deg = 90;
    EXPECT_THROW(validate(p), Error);
    p = {};
    p.min_points = 2;
    EXPECT_THROW(validate(p), Error);
}

}  // namespace
}  // namespace tlsmon::campaign
