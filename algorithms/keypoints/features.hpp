#pragma once
// Keypoints and their descriptors as plain data: what the OpenCV adapter
// (opencv_features.hpp) returns and the pure matching (keypoint_matching.hpp) and the
// reference cache consume.
#include <cstdint>
#include <vector>

namespace tlsmon::keypoints {

struct Keypoint {
    double row = 0, column = 0;  // sub-pixel position (pixel centres at integers)
    float size = 0;              // diameter of the meaningful neighbourhood, pixels
    float angle = -1;            // degrees, −1 when not computed
    float response = 0;          // detector response (strength)
    int octave = 0;              // the detector's scale level (OpenCV's packed value)
    int class_id = -1;           // the detector's own tag (KAZE/AKAZE: the evolution level)
};

// One descriptor per keypoint, row-major: `length` bytes (binary, compared by Hamming
// distance) or `length` floats (compared by Euclidean distance).
struct Descriptors {
    bool binary = true;
    std::size_t length = 0;
    std::vector<std::uint8_t> bits;
    std::vector<float> values;
    std::size_t count() const {
        if (length == 0) return 0;
        return binary ? bits.size() / length : values.size() / length;
    }
};

struct Features {
    std::vector<Keypoint> keypoints;  // keypoints[i] is described by descriptor row i
    Descriptors descriptors;
};

}  // namespace tlsmon::keypoints
