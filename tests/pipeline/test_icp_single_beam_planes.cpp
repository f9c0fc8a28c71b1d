// Where the scan is coarser than the ICP's voxels, every voxel mean is one beam's point, and a
// plane through a few of them leans towards their rows' cones (pipeline/pcl_adapter.hpp,
// surface_with_normals' `min_points`; docs/registration.md, "Planes of single beams"): the
// ICP's surface keeps no such plane, and keeps the planes of surfaces sampled finer.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>
#include <tuple>
#include <vector>

#include "pipeline/icp_registration.hpp"
#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/scene.hpp"
#include "simulator/stable_ground.hpp"
#include "tests/support/stable_band.hpp"

namespace tlsmon {
namespace {

// A level square lattice of `spacing`, each point standing for `count` scan points.
VoxelMeans lattice(double spacing, double count) {
    VoxelMeans m;
    for (int i = 0; i < 30; ++i) {
        for (int j = 0; j < 30; ++j) {
            m.points.emplace_back(i * spacing, j * spacing, 0.0);
            m.counts.push_back(count);
        }
    }
    return m;
}

TEST(IcpSingleBeamPlanes, ANeighbourhoodOfFewScanPointsHoldsNoPlane) {
    const Eigen::Vector3d above(4.0, 4.0, 10.0);
    // 0.17 m apart, a disc of 0.3 m holds 9 means: enough for the shape tests of a plane.
    const VoxelMeans single = lattice(0.17, 1.0);
    const SurfaceSample without =
        surface_with_normals(single.points, 0.3, 0.02, above, single.counts);
    EXPECT_GT(without.points.size(), single.points.size() / 2);
    // Nine scan points, fewer than twelve: no plane.
    const SurfaceSample with =
        surface_with_normals(single.points, 0.3, 0.02, above, single.counts, 0.0, 12.0);
    EXPECT_TRUE(with.points.empty()) << with.points.size() << " kept";
    // The same means standing for two points each hold eighteen: the planes are kept.
    const VoxelMeans doubled = lattice(0.17, 2.0);
    const SurfaceSample kept =
        surface_with_normals(doubled.points, 0.3, 0.02, above, doubled.counts, 0.0, 12.0);
    EXPECT_EQ(kept.points.size(), without.points.size());
}

// `hochmosel` at its own 0.03°: its north slope, 230–320 m out, is sampled 0.12–0.17 m between
// beams, every point its own 0.1 m voxel; the abutment at 60–70 m two to three points a voxel.
TEST(IcpSingleBeamPlanes, HochmoselsFarSlopeLeavesTheSurfaceAndItsAbutmentStays) {
    const sim::Site site = sim::preset("hochmosel");
    const auto boxes = sim::stable_ground(site);
    const double top = test::highest_box_elevation_deg(site, boxes) + 0.5;
    const sim::RenderedScan r =
        test::render_lower_band(site, sim::epoch_conditions(site, 0, 0.0), top, 0.03);
    const auto surface_in = [&](const std::string& name) {
        IcpConfig c;
        for (const auto& b : boxes) {
            if (b.name == name) c.regions.push_back({b.name, b.min, b.max});
        }
        EXPECT_EQ(c.regions.size(), 1u) << name;
        const auto inside = points_in_stable_regions(c, {r.scan}, Eigen::Matrix4d::Identity());
        const VoxelMeans means = voxel_means(inside, c.voxel_size);
        const Eigen::Vector3d o = r.scan.scanner_position();
        return std::tuple{
            inside.size(), means.points.size(),
            surface_with_normals(means.points, 0.3, 0.02, o, means.counts).points.size(),
            surface_with_normals(means.points, 0.3, 0.02, o, means.counts, 0.0, 12.0).points.size(),
            build_stable_surface(c, {r.scan}).sample.points.size()};
    };
    // Each region's points, its means, the means kept by the shape tests alone, by those and
    // twelve scan points, and in the ICP's own reference surface.
    const auto [slope_points, slope_means, slope_shapes, slope_planes, slope_icp] =
        surface_in("valley-side-4");
    EXPECT_GT(slope_points, 200000u);
    EXPECT_GT(static_cast<double>(slope_means), 0.99 * static_cast<double>(slope_points));
    EXPECT_GT(slope_shapes, slope_means / 4) << "the shape tests alone keep its planes";
    EXPECT_EQ(slope_planes, 0u);
    EXPECT_EQ(slope_icp, 0u);
    const auto [abutment_points, abutment_means, abutment_shapes, abutment_planes, abutment_icp] =
        surface_in("A-east");
    EXPECT_GT(abutment_points, 2 * abutment_means);
    EXPECT_GT(static_cast<double>(abutment_planes), 0.95 * static_cast<double>(abutment_shapes));
    EXPECT_GT(abutment_icp, abutment_means / 2);
}

}  // namespace
}  // namespace tlsmon
