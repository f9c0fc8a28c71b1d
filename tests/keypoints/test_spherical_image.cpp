// Spherical images of the real structured scan pumpA_from_e57.ptx (INVENTORY.md: 1074 rows ×
// 345 columns, 155,201 returns, azimuth −2.58…−1.08 rad, elevation −0.785…0.481 rad), the
// same scan turned so that it straddles azimuth ±π (no wrap artefacts), and the binning of
// an unstructured scan.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "algorithms/keypoints/spherical_image.hpp"
#include "core/error.hpp"
#include "tests/keypoints/real_scan.hpp"

namespace {

using namespace tlsmon;
using namespace tlsmon::keypoints;

TEST(SphericalImage, PumpScanHasTheGridsSizeAndReturns) {
    const SphericalImages im = spherical_images_from_grid(test::pump_scan());
    EXPECT_EQ(im.rows, 1074);
    EXPECT_EQ(im.columns, 345);
    EXPECT_EQ(im.valid.count(), 155201);
    // Photograph orientation: elevation falls with the row, azimuth with the column, and the
    // lattice spans the file's spherical bounds (to a step at each end).
    EXPECT_NEAR(im.row_elevation(0), 0.481, 2 * im.elevation_step + 0.001);
    EXPECT_NEAR(im.row_elevation(im.rows - 1), -0.785, 2 * im.elevation_step + 0.001);
    EXPECT_NEAR(im.column_azimuth(0), -1.08, 2 * im.azimuth_step + 0.005);
    EXPECT_NEAR(im.column_azimuth(im.columns - 1), -2.58, 2 * im.azimuth_step + 0.005);
    EXPECT_NEAR(im.elevation_step, (0.481 + 0.785) / 1073, 0.05 * im.elevation_step);
    EXPECT_NEAR(im.azimuth_step, (2.58 - 1.08) / 344, 0.05 * im.azimuth_step);
    for (Eigen::Index r = 1; r < im.rows; ++r)
        ASSERT_LT(im.row_elevation(r), im.row_elevation(r - 1));
    for (Eigen::Index c = 1; c < im.columns; ++c)
        ASSERT_LT(im.column_azimuth(c), im.column_azimuth(c - 1));
    // Every return's own angles lie within one and a half steps of its pixel's lattice angles
    // (this file's rows and columns are not exact lines of constant angle: about a third of
    // its returns lie more than half a step off their row's or column's median), and its
    // range within the file's 1.98–5.43 m.
    std::size_t off_centre = 0;
    for (Eigen::Index r = 0; r < im.rows; ++r)
        for (Eigen::Index c = 0; c < im.columns; ++c) {
            if (!im.valid(r, c)) continue;
            const double da = std::abs(im.azimuth(r, c) - im.column_azimuth(c)) / im.azimuth_step;
            const double de =
                std::abs(im.elevation(r, c) - im.row_elevation(r)) / im.elevation_step;
            off_centre += da > 0.5 || de > 0.5;
            ASSERT_LT(da, 1.5);
            ASSERT_LT(de, 1.5);
            ASSERT_GE(im.range(r, c), 1.97);
            ASSERT_LE(im.range(r, c), 5.44);
        }
    EXPECT_LT(off_centre, 155201 / 2);
}

TEST(SphericalImage, ScanAcrossPlusMinusPiHasNoWrapArtefacts) {
    const Scan& original = test::pump_scan();
    const SphericalImages a = spherical_images_from_grid(original);
    // Turn the scan about the scanner's z axis so that its middle azimuth (≈ −1.83 rad) lands
    // on π: half its columns then have azimuths near +π, half near −π.
    const double turn = std::numbers::pi + 1.83;
    Scan turned = original;
    const Eigen::Matrix3d rz = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    for (auto& p : turned.xyz) p = rz * p;
    const SphericalImages b = spherical_images_from_grid(turned);
    ASSERT_EQ(b.rows, a.rows);
    ASSERT_EQ(b.columns, a.columns);
    EXPECT_TRUE((b.valid == a.valid).all());
    EXPECT_LT((b.intensity - a.intensity).abs().maxCoeff(), 1e-12);
    EXPECT_LT((b.range - a.range).abs().maxCoeff(), 1e-9);
    EXPECT_LT((b.elevation - a.elevation).abs().maxCoeff(), 1e-9);
    // Straddles ±π indeed, and yet the lattice and every pixel's azimuth are continuous:
    // the turned azimuth minus the original is the turn (mod 2π) everywhere, and neighbouring
    // columns differ by one step.
    EXPECT_GT(b.column_azimuth.maxCoeff() - b.column_azimuth.minCoeff(), 1.4);
    for (Eigen::Index c = 1; c < b.columns; ++c)
        ASSERT_NEAR(b.column_azimuth(c - 1) - b.column_azimuth(c), b.azimuth_step,
                    0.5 * b.azimuth_step);
    for (Eigen::Index r = 0; r < b.rows; ++r)
        for (Eigen::Index c = 1; c < b.columns; ++c) {
            if (!b.valid(r, c)) continue;
            ASSERT_NEAR(wrapped_difference(b.azimuth(r, c), a.azimuth(r, c) + turn), 0.0, 1e-9);
            if (b.valid(r, c - 1)) {
                ASSERT_LT(std::abs(b.azimuth(r, c - 1) - b.azimuth(r, c)), 3 * b.azimuth_step);
            }
        }
}

TEST(SphericalImage, BinnedScanMatchesTheGridAndLeavesGapsEmpty) {
    const Scan& structured = test::pump_scan();
    const SphericalImages grid = spherical_images_from_grid(structured);
    Scan loose = structured;
    loose.grid.reset();
    // A hole of 30 × 30 grid pixels cut where the scan has the most returns: it must stay
    // empty.
    Eigen::Index top = 0, left = 0, most = -1;
    for (Eigen::Index r = 0; r + 30 <= grid.rows; r += 10)
        for (Eigen::Index c = 0; c + 30 <= grid.columns; c += 10) {
            const Eigen::Index n = grid.valid.block(r, c, 30, 30).count();
            if (n > most) {
                most = n;
                top = r;
                left = c;
            }
        }
    ASSERT_GT(most, 600);
    const double az_hi = grid.column_azimuth(left), az_lo = grid.column_azimuth(left + 30);
    const double el_hi = grid.row_elevation(top), el_lo = grid.row_elevation(top + 30);
    Scan holed;
    holed.source = "holed";
    for (std::size_t i = 0; i < loose.size(); ++i) {
        const Polar q = polar_of(loose.xyz[i]);
        if (q.azimuth < az_hi && q.azimuth > az_lo && q.elevation < el_hi && q.elevation > el_lo)
            continue;
        holed.xyz.push_back(loose.xyz[i]);
        holed.intensity.push_back(loose.intensity[i]);
    }
    ASSERT_LT(holed.size(), loose.size());
    const SphericalImages b =
        spherical_images_binned(holed, {grid.azimuth_step, grid.elevation_step});
    // The lattice is anchored at zero, the grid's is not: sizes agree within a pixel.
    EXPECT_NEAR(static_cast<double>(b.rows), 1074.0, 1.0);
    EXPECT_NEAR(static_cast<double>(b.columns), 345.0, 1.0);
    // Most returns keep a pixel of their own (a real scanner's angles jitter a little around
    // its lattice, so a few share one); none is invented.
    EXPECT_GT(b.valid.count(), static_cast<Eigen::Index>(0.9 * static_cast<double>(holed.size())));
    EXPECT_LE(b.valid.count(), static_cast<Eigen::Index>(holed.size()));
    for (Eigen::Index r = 0; r < b.rows; ++r)
        for (Eigen::Index c = 0; c < b.columns; ++c) {
            const double az = b.column_azimuth(c), el = b.row_elevation(r);
            const bool inside_hole = az < az_hi - b.azimuth_step && az > az_lo + b.azimuth_step &&
                                     el < el_hi - b.elevation_step && el > el_lo + b.elevation_step;
            if (inside_hole) {
                ASSERT_FALSE(b.valid(r, c)) << r << ", " << c;
            }
            if (b.valid(r, c)) {
                ASSERT_LE(std::abs(b.azimuth(r, c) - az), 0.5 * b.azimuth_step + 1e-12);
                ASSERT_LE(std::abs(b.elevation(r, c) - el), 0.5 * b.elevation_step + 1e-12);
            }
        }
}

TEST(SphericalImage, EightBitStretchAndDetectionMask) {
    const SphericalImages im = spherical_images_from_grid(test::pump_scan());
    const Raster8 grey = intensity_to_8bit(im);
    ASSERT_EQ(grey.rows, 1074);
    ASSERT_EQ(grey.columns, 345);
    // The 0.5 % and 99.5 % quantiles go to 0 and 255: about 0.5 % of the returns at each end.
    std::size_t black = 0, white = 0;
    for (Eigen::Index r = 0; r < im.rows; ++r)
        for (Eigen::Index c = 0; c < im.columns; ++c)
            if (im.valid(r, c)) {
                black += grey.at(int(r), int(c)) == 0;
                white += grey.at(int(r), int(c)) == 255;
            }
    EXPECT_NEAR(double(black) / 155201, 0.005, 0.004);
    EXPECT_NEAR(double(white) / 155201, 0.005, 0.004);
    // The mask: a pixel is kept exactly when its 5 × 5 neighbourhood lies inside the image
    // and has returns everywhere.
    const Raster8 mask = detection_mask(im, 2);
    for (Eigen::Index r = 0; r < im.rows; ++r)
        for (Eigen::Index c = 0; c < im.columns; ++c) {
            bool all = r >= 2 && c >= 2 && r + 2 < im.rows && c + 2 < im.columns;
            for (Eigen::Index dr = -2; all && dr <= 2; ++dr)
                for (Eigen::Index dc = -2; all && dc <= 2; ++dc) all = im.valid(r + dr, c + dc);
            ASSERT_EQ(mask.at(int(r), int(c)), all ? 255 : 0) << r << ", " << c;
        }
}

TEST(SphericalImage, ClearErrors) {
    Scan s;
    s.source = "no-grid.xyz";
    s.xyz = {Eigen::Vector3d(1, 0, 0)};
    s.intensity = {0.5f};
    try {
        spherical_images_from_grid(s);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no-grid.xyz"), std::string::npos);
    }
    s.intensity.clear();
    EXPECT_THROW(spherical_images_binned(s, {0.001, 0.001}), Error);
    s.intensity = {0.5f};
    EXPECT_THROW(spherical_images_binned(s, {0.0, 0.001}), Error);
}

}  // namespace
