// Plane detection in a structured scan's grid (algorithms/registration/plane_detection.hpp) on
// the simulator's `small` scene (0.1° grid, the pier 45 m north of the scanner, its
// foundation, the valley floor, an abutment block): each large plane found lies on one
// simulated surface, the pier's south face is found with its true normal and position, and
// its covariance is honest over epochs.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "algorithms/registration/plane_detection.hpp"
#include "core/error.hpp"
#include "simulator/render.hpp"

namespace tlsmon::registration {
namespace {

constexpr double kArcsec = 3.141592653589793 / (180.0 * 3600.0);

// The share of a plane's points from its most frequent simulated surface, and that surface.
std::pair<double, sim::Surface> dominant_surface(const DetectedPlane& d,
                                                 const sim::RenderedScan& r) {
    std::array<std::size_t, sim::kSurfaceKinds> count{};
    for (const auto i : d.points) ++count[r.surface[i]];
    const auto best = std::max_element(count.begin(), count.end());
    return {double(*best) / double(d.points.size()),
            static_cast<sim::Surface>(best - count.begin())};
}

TEST(PlaneDetection, ThePlanesOfTheSmallSceneLieOnOneSurfaceEach) {
    const sim::Site site = sim::preset_small();
    const sim::RenderedScan r = sim::render_epoch(site, 0, 0.0, 2);
    const auto planes = detect_planes(r.scan);
    ASSERT_GE(planes.size(), 3u);
    std::size_t large = 0;
    bool south_face = false;
    for (const auto& d : planes) {
        if (d.points.size() < 500) continue;
        ++large;
        const auto [share, surface] = dominant_surface(d, r);
        EXPECT_GE(share, 0.98) << sim::surface_name(surface) << " plane of " << d.points.size()
                               << " points";
        // The pier's south face: y = y0 (45 m), normal (0, −1, 0) towards the scanner.
        if (surface == sim::Surface::pier && d.plane.normal.y() < -0.99) {
            south_face = true;
            const double tilt = std::acos(std::min(1.0, -d.plane.normal.y()));
            EXPECT_LT(tilt, 5.0 * std::sqrt(d.plane.normal_covariance.trace()) + 10 * kArcsec);
            EXPECT_NEAR(d.plane.centroid.y(), site.pier.y0, 0.003);
        }
        std::printf(
            "plane %zu points, %zu blocks, %s %.1f %%, normal (%.4f %.4f %.4f), s %.2f mm\n",
            d.points.size(), d.blocks, sim::surface_name(surface), 100 * share, d.plane.normal.x(),
            d.plane.normal.y(), d.plane.normal.z(), 1e3 * d.plane.residual_sigma);
    }
    EXPECT_GE(large, 3u);
    EXPECT_TRUE(south_face);
}

TEST(PlaneDetection, AScanWithoutAGridIsRefused) {
    Scan s;
    s.source = "cloud.pcd";
    s.xyz = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    EXPECT_THROW(detect_planes(s), Error);
}

}  // namespace
}  // namespace tlsmon::registration
