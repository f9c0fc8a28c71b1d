#pragma once
// Spherical images of one scan: intensity, range and the angles of each return on the
// scanner's own angular lattice, one pixel per horizontal (column) and vertical (row) angle
// step. Keypoints are detected in the intensity image; the range and angle images take a
// keypoint back to 3-D (keypoint_to_3d.hpp).
//
// Image orientation is that of a photograph taken from the scanner looking out: row 0 is the
// highest elevation, column 0 the largest azimuth (azimuth φ counter-clockwise from the
// scanner's +x axis seen from above, elevation e from the horizontal; docs/simulator.md).
// Azimuths are unwrapped so that they are continuous across the image: a scan that straddles
// φ = ±π has azimuths beyond π on one side, never a 2π jump between neighbouring pixels.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "algorithms/image.hpp"
#include "core/scan.hpp"

namespace tlsmon::keypoints {

// Scanner-frame polar coordinates: range (m), azimuth φ = atan2(y, x) in (−π, π] and
// elevation e = atan2(z, √(x² + y²)) (rad); the beam direction is
// d(φ, e) = (cos e cos φ, cos e sin φ, sin e).
struct Polar {
    double range = 0, azimuth = 0, elevation = 0;
};
Polar polar_of(const Eigen::Vector3d& scanner_point);
Eigen::Vector3d cartesian_of(const Polar& polar);

// An angle difference a − b brought into (−π, π].
double wrapped_difference(double a, double b);

struct SphericalImages {
    Eigen::Index rows = 0, columns = 0;
    ImageMask valid;            // a return in the pixel
    Eigen::ArrayXXd intensity;  // 0..1 (Scan::intensity); 0 where !valid
    Eigen::ArrayXXd range;      // m; 0 where !valid
    Eigen::ArrayXXd azimuth;    // rad, the return's own, unwrapped (see above); 0 where !valid
    Eigen::ArrayXXd elevation;  // rad, the return's own; 0 where !valid
    // The lattice: the nominal angle of each column and row (a structured scan: the median
    // over the column's or row's returns, columns or rows without any continued at the
    // median step; a binned scan: the bin centres). Azimuth decreases with the column,
    // elevation with the row. Keypoints are placed by these angles for matching.
    Eigen::ArrayXd column_azimuth;
    Eigen::ArrayXd row_elevation;
    double azimuth_step = 0, elevation_step = 0;         // rad, > 0
    Eigen::Affine3d pose = Eigen::Affine3d::Identity();  // scanner -> project frame (Scan::pose)

    // The lattice's angles at a sub-pixel position (linear between pixel centres, continued
    // at the step beyond the image's edges).
    double azimuth_at(double column) const;
    double elevation_at(double row) const;
};

// From a structured scan: pixel (row, column) is the grid's cell, with the grid's rows and
// columns reversed where needed for the orientation above. Throws tlsmon::Error when the
// scan has no grid, no intensity, or no returns, naming Scan::source.
SphericalImages spherical_images_from_grid(const Scan& scan);

// From an unstructured scan: each return binned on the lattice φ = k · azimuth_step,
// e = m · elevation_step (anchored at zero, so two epochs of one station share the lattice);
// where several returns fall in one pixel, the one nearest the pixel's centre is kept (never
// an average, which would mix the two sides of a depth edge). Pixels without a return stay
// empty: gaps are not filled. Throws for non-positive steps, a scan without intensity, or a
// lattice over max_pixels.
struct Binning {
    double azimuth_step = 0;    // rad
    double elevation_step = 0;  // rad
    std::uint64_t max_pixels = 200'000'000;
};
SphericalImages spherical_images_binned(const Scan& scan, const Binning& binning);

// An 8-bit grey image, row-major.
struct Raster8 {
    int rows = 0, columns = 0;
    std::vector<std::uint8_t> pixels;
    std::uint8_t at(int row, int column) const {
        return pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(columns) +
                      static_cast<std::size_t>(column)];
    }
};

// Intensity to 8 bit: a linear stretch of the valid pixels' [low, high] quantiles to
// 0..255 (clipped), so a few specular returns do not compress the rest; empty pixels take
// the median's grey, so that they make no strong edge (detection is masked there anyway).
Raster8 intensity_to_8bit(const SphericalImages& images, double low_quantile = 0.005,
                          double high_quantile = 0.995);

// Where keypoints may be detected: valid pixels at least `margin` pixels (Chebyshev) from
// any empty pixel or the image's border, as 255, else 0. Keypoints on the rim of a hole or
// of the sky are the contrast of "return / no return", not of the surface.
Raster8 detection_mask(const SphericalImages& images, int margin);

// The pixels whose return lies, in the project frame (the scan's pose applied), inside one of
// the boxes: the zones of interest. Applied to a detection mask it confines detection to
// them, and the detector's work to their bounding rectangle in the image.
ImageMask pixels_in_boxes(const SphericalImages& images,
                          const std::vector<Eigen::AlignedBox3d>& project_boxes);
void restrict_mask(Raster8& mask, const ImageMask& region);

}  // namespace tlsmon::keypoints
