// Known answers for the orthoimage: a linear intensity field is reproduced at the pixel
// centres (a symmetric Gaussian average of a linear function is its centre value), on an
// axis-aligned and on a tilted plane; points beyond max_distance leave no trace; a hole in
// the points leaves masked pixels.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/orthoimage.hpp"
#include "core/error.hpp"

namespace tlsmon::test {
namespace {

double linear(const Eigen::Vector2d& q) {
    return 0.4 + 0.8 * q.x() - 0.5 * q.y();
}

// Points on a square lattice of spacing h over [0, 0.4]² of the plane, intensity linear in
// (u, v), plus points 0.2 m off the plane with intensity 1, which must be ignored.
struct Cloud {
    std::vector<Eigen::Vector3d> xyz;
    std::vector<float> intensity;
};

Cloud lattice(const OrthoPlane& plane, double h, bool hole) {
    Cloud c;
    const Eigen::Vector3d n = plane.u.cross(plane.v);
    const int count = static_cast<int>(std::lround(0.4 / h));
    for (int i = 0; i <= count; ++i) {
        for (int j = 0; j <= count; ++j) {
            const Eigen::Vector2d q(i * h, j * h);
            if (hole && (q - Eigen::Vector2d(0.2, 0.2)).norm() < 0.05) continue;
            c.xyz.push_back(plane.origin + q.x() * plane.u + q.y() * plane.v);
            c.intensity.push_back(static_cast<float>(linear(q)));
            c.xyz.push_back(c.xyz.back() + 0.2 * n);
            c.intensity.push_back(1.0f);
        }
    }
    return c;
}

OrthoGrid grid_over_the_middle() {
    OrthoGrid g;
    g.pixel_size = 0.01;  // pixel centres on lattice points: symmetric neighbourhoods
    g.first_centre = {0.1, 0.1};
    g.rows = 21;
    g.columns = 21;
    g.kernel_sigma = 0.006;
    return g;
}

void expect_linear_field(const Orthoimage& im, double tolerance) {
    for (Eigen::Index r = 0; r < im.grid.rows; ++r) {
        for (Eigen::Index c = 0; c < im.grid.columns; ++c) {
            ASSERT_TRUE(im.image.valid(r, c)) << r << " " << c;
            // Intensities are floats: 6e-8 relative.
            EXPECT_NEAR(im.image.value(r, c),
                        linear(im.pixel_centre(static_cast<double>(r), static_cast<double>(c))),
                        tolerance);
        }
    }
}

TEST(Orthoimage, LinearIntensityIsReproducedAtPixelCentres) {
    OrthoPlane plane;
    plane.origin = {2.0, 45.0, 10.0};
    plane.max_distance = 0.05;
    const Cloud c = lattice(plane, 0.005, false);
    expect_linear_field(rasterise_orthoimage(c.xyz, c.intensity, plane, grid_over_the_middle()),
                        1e-6);
}

TEST(Orthoimage, TiltedPlaneProjectsOntoItsOwnAxes) {
    OrthoPlane plane;
    plane.origin = {-3.0, 7.0, 1.0};
    const Eigen::Vector3d u = Eigen::Vector3d(1.0, 2.0, 0.5).normalized();
    plane.u = u;
    plane.v = u.cross(Eigen::Vector3d(0.3, -0.2, 1.0)).normalized();
    plane.max_distance = 0.05;
    const Cloud c = lattice(plane, 0.005, false);
    expect_linear_field(rasterise_orthoimage(c.xyz, c.intensity, plane, grid_over_the_middle()),
                        1e-6);
}

TEST(Orthoimage, HoleInThePointsIsMaskedAndTheRestValid) {
    OrthoPlane plane;
    const Cloud c = lattice(plane, 0.005, true);
    OrthoGrid g = grid_over_the_middle();
    const Orthoimage im = rasterise_orthoimage(c.xyz, c.intensity, plane, g);
    for (Eigen::Index r = 0; r < g.rows; ++r) {
        for (Eigen::Index col = 0; col < g.columns; ++col) {
            const double d = (im.pixel_centre(static_cast<double>(r), static_cast<double>(col)) -
                              Eigen::Vector2d(0.2, 0.2))
                                 .norm();
            // Nearest point at d − 0.05 from inside the hole: empty when beyond 2 σ_s.
            if (d < 0.05 - 2.0 * g.kernel_sigma - 0.003) {
                EXPECT_FALSE(im.image.valid(r, col));
            }
            if (d > 0.05) {
                EXPECT_TRUE(im.image.valid(r, col));
            }
        }
    }
}

TEST(Orthoimage, BadPlaneOrGridIsAnError) {
    OrthoPlane plane;
    plane.v = Eigen::Vector3d(0.1, 0.0, 1.0);  // not orthogonal to u, not unit
    const std::vector<Eigen::Vector3d> xyz{Eigen::Vector3d::Zero()};
    const std::vector<float> intensity{0.5f};
    EXPECT_THROW(rasterise_orthoimage(xyz, intensity, plane, grid_over_the_middle()), Error);
    OrthoGrid g = grid_over_the_middle();
    g.pixel_size = 0.0;
    EXPECT_THROW(rasterise_orthoimage(xyz, intensity, OrthoPlane{}, g), Error);
    EXPECT_THROW(rasterise_orthoimage(xyz, {}, OrthoPlane{}, grid_over_the_middle()), Error);
}

}  // namespace
}  // namespace tlsmon::test
