#pragma once
// Keypoints in spherical intensity images through OpenCV, the project's only OpenCV file
// pair (library tlsmon_keypoints_opencv): detector and descriptor chosen by name, optional
// CLAHE, and a picture of the matches for a person to look at. The interface is plain data;
// matching and everything after it are pure (keypoint_matching.hpp, keypoint_to_3d.hpp).
//
// Detectors: "kaze" (default: the Hessian-determinant response of SURF, which Debian's
// OpenCV lacks, in a nonlinear scale space; Alcantarilla et al. 2012), "akaze", "sift",
// "brisk", "orb". Descriptors: "brisk" (default; binary, Hamming distance), "sift", "orb",
// "kaze" and "akaze" (the last two only on their own detector's keypoints, whose scale
// level they need).
#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/keypoints/feature_parameters.hpp"
#include "algorithms/keypoints/features.hpp"
#include "algorithms/keypoints/spherical_image.hpp"

namespace tlsmon::keypoints {

// The image detection and description both work on: the 8-bit intensity, equalised when
// `clahe` is set.
Raster8 prepared_image(const Raster8& image, const FeatureParameters& parameters);

// Keypoints where `mask` is non-zero (an empty mask: everywhere).
std::vector<Keypoint> detect_keypoints(const Raster8& image, const Raster8& mask,
                                       const FeatureParameters& parameters);

// Descriptors of the keypoints. Descriptors drop keypoints they cannot describe (BRISK and
// ORB near the border): the result keeps only the described ones, each with the detector's
// own position, size and response (BRISK overwrites the angle, SIFT's packed octave is reset
// before another descriptor sees it).
Features describe_keypoints(const Raster8& image, const std::vector<Keypoint>& keypoints,
                            const FeatureParameters& parameters);

// A picture for a person: the image in grey, each match as a circle at its position and a
// line towards where it moved, drawn `vector_scale` times its length; green when kept, red
// when removed. (formats/png_file.hpp writes it.)
struct DrawnMatch {
    double row = 0, column = 0;
    double to_row = 0, to_column = 0;
    bool kept = true;
};
struct RasterRgb {
    int rows = 0, columns = 0;
    std::vector<std::uint8_t> pixels;  // row by row, red, green, blue per pixel
};
RasterRgb draw_matches(const Raster8& image, const std::vector<DrawnMatch>& matches,
                       double vector_scale);

}  // namespace tlsmon::keypoints
