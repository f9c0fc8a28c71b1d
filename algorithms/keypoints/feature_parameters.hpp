#pragma once
// What the OpenCV adapter (opencv_features.hpp) detects and describes with, and its check:
// plain data, so that the configuration is checked without linking OpenCV.
#include <string>

#include "algorithms/keypoints/parameters.hpp"

namespace tlsmon::keypoints {

struct FeatureParameters {
    std::string detector = Parameters{}.detector;
    std::string descriptor = Parameters{}.descriptor;
    // Contrast-limited adaptive histogram equalisation of the 8-bit image before detection
    // and description (Zuiderveld 1994): clip limit and tiles per side.
    bool clahe = false;
    double clahe_clip_limit = 2.0;
    int clahe_tiles = 8;
    double detector_threshold = Parameters{}.detector_threshold;  // KAZE/AKAZE only
    // KAZE/AKAZE scale space: octaves and sub-levels per octave (OpenCV's defaults, 4 and 4).
    // KAZE keeps every level at full resolution, so its time and memory grow with their
    // product times the image's pixels (≈ 16 float images per level).
    int kaze_octaves = 4;
    int kaze_octave_layers = 4;
    int max_keypoints = 0;  // keep the strongest N; 0: all
};

// The detector's and descriptor's part of the method's parameters.
FeatureParameters features_of(const Parameters& parameters);

// Throws tlsmon::Error naming the unknown detector or descriptor, or a pair that does not
// work together.
void validate(const FeatureParameters& parameters);

}  // namespace tlsmon::keypoints
