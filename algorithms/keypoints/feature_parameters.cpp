#include "algorithms/keypoints/feature_parameters.hpp"

#include <algorithm>
#include <vector>

#include "core/error.hpp"

namespace tlsmon::keypoints {

namespace {

const std::vector<std::string> detectors = {"kaze", "akaze", "sift", "brisk", "orb"};
const std::vector<std::string> descriptors = {"brisk", "sift", "orb", "kaze", "akaze"};

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

}  // namespace

FeatureParameters features_of(const Parameters& parameters) {
    FeatureParameters f;
    f.detector = parameters.detector;
    f.descriptor = parameters.descriptor;
    f.clahe = parameters.clahe;
    f.detector_threshold = parameters.detector_threshold;
    return f;
}

void validate(const FeatureParameters& p) {
    if (std::find(detectors.begin(), detectors.end(), p.detector) == detectors.end())
        throw Error("keypoints: unknown detector '" + p.detector + "' (one of " +
                    joined(detectors) + ")");
    if (std::find(descriptors.begin(), descriptors.end(), p.descriptor) == descriptors.end())
        throw Error("keypoints: unknown descriptor '" + p.descriptor + "' (one of " +
                    joined(descriptors) + ")");
    if ((p.descriptor == "kaze" || p.descriptor == "akaze") && p.detector != p.descriptor)
        throw Error("keypoints: the '" + p.descriptor + "' descriptor needs the '" + p.descriptor +
                    "' detector (it reads the detector's scale level)");
    if (p.clahe && (!(p.clahe_clip_limit > 0.0) || p.clahe_tiles < 1))
        throw Error("keypoints: CLAHE needs a clip limit > 0 and at least one tile");
    if (!(p.detector_threshold > 0.0)) throw Error("keypoints: detector_threshold must be > 0");
    if (p.kaze_octaves < 1 || p.kaze_octave_layers < 1)
        throw Error("keypoints: kaze_octaves and kaze_octave_layers must be >= 1");
    if (p.max_keypoints < 0) throw Error("keypoints: max_keypoints must be >= 0");
}

}  // namespace tlsmon::keypoints
