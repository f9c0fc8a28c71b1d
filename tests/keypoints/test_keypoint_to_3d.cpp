// Keypoints back to 3-D on synthetic spherical images of a wall at x = 5 m: at pixel centres
// the interpolated polar coordinates are the pixel's own, between them the point lies on the
// wall; empty neighbours and depth edges drop the keypoint; the ±π wrap between the four
// pixels does not enter the mean; the scanner -> project transform is applied.
#include <gtest/gtest.h>

#include <numbers>

#include "algorithms/keypoints/keypoint_to_3d.hpp"

namespace {

using namespace tlsmon::keypoints;

// A wall x = distance seen on a lattice of `rows` × `columns` pixels around azimuth `centre`.
SphericalImages wall(double distance, double centre = 0.0, Eigen::Index rows = 20,
                     Eigen::Index columns = 30, double step = 0.001) {
    SphericalImages im;
    im.rows = rows;
    im.columns = columns;
    im.valid = tlsmon::ImageMask::Constant(rows, columns, true);
    im.intensity = Eigen::ArrayXXd::Constant(rows, columns, 0.5);
    im.range.resize(rows, columns);
    im.azimuth.resize(rows, columns);
    im.elevation.resize(rows, columns);
    im.column_azimuth.resize(columns);
    im.row_elevation.resize(rows);
    im.azimuth_step = im.elevation_step = step;
    for (Eigen::Index c = 0; c < columns; ++c)
        im.column_azimuth(c) =
            centre + step * (static_cast<double>(columns) / 2 - static_cast<double>(c));
    for (Eigen::Index r = 0; r < rows; ++r)
        im.row_elevation(r) = step * (static_cast<double>(rows) / 2 - static_cast<double>(r));
    for (Eigen::Index r = 0; r < rows; ++r)
        for (Eigen::Index c = 0; c < columns; ++c) {
            const double az = im.column_azimuth(c), el = im.row_elevation(r);
            // The wall turned with the lattice: its normal points along the centre azimuth.
            const double local = az - centre;
            const double range = distance / (std::cos(el) * std::cos(local));
            im.range(r, c) = range;
            im.azimuth(r, c) = az;
            im.elevation(r, c) = el;
        }
    return im;
}

TEST(KeypointTo3d, PixelCentresAndPointsBetweenThemLieOnTheWall) {
    const SphericalImages im = wall(5.0);
    const PolarAt at = polar_at(im, 7.0, 11.0);
    ASSERT_EQ(at.dropped, Dropped::no);
    EXPECT_DOUBLE_EQ(at.polar.range, im.range(7, 11));
    EXPECT_DOUBLE_EQ(at.polar.azimuth, im.azimuth(7, 11));
    EXPECT_DOUBLE_EQ(at.polar.elevation, im.elevation(7, 11));
    // Between centres: on the plane x = 5 to the error of interpolating the range linearly
    // (r'' · t(1 − t) · h² / 2 per axis, r'' ≈ r per rad²: ≈ 0.6 µm for h = 1 mrad at 5 m),
    // and at the interpolated angles.
    const PolarAt mid = polar_at(im, 7.25, 11.6);
    ASSERT_EQ(mid.dropped, Dropped::no);
    EXPECT_NEAR(cartesian_of(mid.polar).x(), 5.0, 2e-6);
    EXPECT_NEAR(mid.polar.azimuth, im.azimuth_at(11.6), 1e-12);
    EXPECT_NEAR(mid.polar.elevation, im.elevation_at(7.25), 1e-12);
    // The last row and column are reachable.
    EXPECT_EQ(polar_at(im, 19.0, 29.0).dropped, Dropped::no);
    EXPECT_EQ(polar_at(im, 19.01, 3.0).dropped, Dropped::outside);
    EXPECT_EQ(polar_at(im, -0.01, 3.0).dropped, Dropped::outside);
}

TEST(KeypointTo3d, EmptyNeighbourAndDepthEdgeDropTheKeypoint) {
    SphericalImages im = wall(5.0);
    im.valid(4, 5) = false;
    EXPECT_EQ(polar_at(im, 3.5, 4.5).dropped, Dropped::empty_neighbour);
    EXPECT_EQ(polar_at(im, 4.5, 5.5).dropped, Dropped::empty_neighbour);
    EXPECT_EQ(polar_at(im, 4.5, 6.5).dropped, Dropped::no);
    // A step of 0.2 m (beyond 5 cm and 2 % of 5 m) between columns 20 and 21.
    for (Eigen::Index r = 0; r < im.rows; ++r)
        for (Eigen::Index c = 21; c < im.columns; ++c) im.range(r, c) += 0.2;
    EXPECT_EQ(polar_at(im, 10.5, 20.5).dropped, Dropped::depth_edge);
    EXPECT_EQ(polar_at(im, 10.5, 21.5).dropped, Dropped::no);
    // A smaller step passes with a looser tolerance only.
    EXPECT_EQ(polar_at(im, 10.5, 20.5, {0.3, 0.0}).dropped, Dropped::no);
}

TEST(KeypointTo3d, FourPixelsAcrossPlusMinusPi) {
    // Columns on either side of azimuth π, stored as the scan gives them: +π − ε and −π + ε.
    // Lattice π + 0.0015, π + 0.0005, π − 0.0005, π − 0.0015: columns 1 and 2 straddle ±π.
    SphericalImages im = wall(5.0, std::numbers::pi - 0.0005, 4, 4);
    for (Eigen::Index r = 0; r < im.rows; ++r)
        for (Eigen::Index c = 0; c < im.columns; ++c)
            im.azimuth(r, c) = std::remainder(im.azimuth(r, c), 2 * std::numbers::pi);
    ASSERT_LT(im.azimuth(0, 1), -3.0);
    ASSERT_GT(im.azimuth(0, 2), 3.0);
    const PolarAt at = polar_at(im, 1.0, 1.5);
    ASSERT_EQ(at.dropped, Dropped::no);
    EXPECT_NEAR(wrapped_difference(at.polar.azimuth, std::numbers::pi), 0.0, 1e-12);
    EXPECT_NEAR(cartesian_of(at.polar).x(), -5.0, 2e-5);
}

TEST(KeypointTo3d, MatchesCarryBothPointsInTheProjectFrame) {
    const SphericalImages a = wall(5.0);
    const SphericalImages b = wall(5.003);  // the wall moved 3 mm away from the scanner
    Eigen::Affine3d to_project = Eigen::Affine3d::Identity();
    to_project.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
    to_project.pretranslate(Eigen::Vector3d(100, 200, 10));
    std::vector<Keypoint> ka(3), kb(3);
    ka[0].row = 5;
    ka[0].column = 6;
    kb[0].row = 5;
    kb[0].column = 6;
    ka[1].row = 8.5;  // its epoch keypoint lies outside the image
    ka[1].column = 9.5;
    kb[1].row = 25;
    kb[1].column = 9;
    ka[2].row = 12.25;
    ka[2].column = 14.75;
    kb[2].row = 12.25;
    kb[2].column = 14.75;
    const std::vector<KeypointPair> pairs = {{0, 0, 3.0}, {1, 1, 4.0}, {2, 2, 5.0}};
    const MatchesIn3d out = matches_to_3d(a, ka, to_project, b, kb, to_project, pairs);
    ASSERT_EQ(out.matches.size(), 2u);
    EXPECT_EQ(out.dropped_outside, 1u);
    const KeypointMatch& m = out.matches[0];
    EXPECT_EQ(m.reference_row, 5.0);
    EXPECT_EQ(m.column, 6.0);
    EXPECT_EQ(m.descriptor_distance, 3.0);
    EXPECT_EQ(m.segment, -1);
    const Eigen::Vector3d scanner_a =
        cartesian_of({a.range(5, 6), a.azimuth(5, 6), a.elevation(5, 6)});
    EXPECT_LT((m.reference_point - to_project * scanner_a).norm(), 1e-9);
    // Along the beam, the x-component of the move is exactly 3 mm in the scanner frame.
    const Eigen::Vector3d d = to_project.linear().transpose() * m.displacement();
    EXPECT_NEAR(d.x(), 0.003, 1e-9);
    // Between pixel centres: both points on their walls.
    const KeypointMatch& n = out.matches[1];
    EXPECT_NEAR((to_project.inverse() * n.reference_point).x(), 5.0, 1e-6);
    EXPECT_NEAR((to_project.inverse() * n.point).x(), 5.003, 1e-6);
}

}  // namespace
