#include "algorithms/keypoints/opencv_features.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.hpp"

namespace tlsmon::keypoints {

namespace {

cv::Mat view_of(const Raster8& image) {
    // OpenCV does not write through this view; the const_cast only meets its signature.
    return cv::Mat(image.rows, image.columns, CV_8UC1,
                   const_cast<std::uint8_t*>(image.pixels.data()));
}

cv::Ptr<cv::Feature2D> create(const std::string& name, const FeatureParameters& p,
                              bool for_detection) {
    const auto threshold = static_cast<float>(p.detector_threshold);
    if (name == "kaze") return cv::KAZE::create(false, false, threshold);
    if (name == "akaze") return cv::AKAZE::create(cv::AKAZE::DESCRIPTOR_MLDB, 0, 3, threshold);
    if (name == "sift") return cv::SIFT::create();
    if (name == "brisk") return cv::BRISK::create();
    if (name == "orb") {
        // ORB keeps its N best by default (500): as a detector, as many as asked or all.
        const int n = for_detection ? (p.max_keypoints > 0 ? p.max_keypoints : 1'000'000) : 500;
        return cv::ORB::create(n);
    }
    throw Error("keypoints: unknown detector or descriptor '" + name + "'");
}

cv::KeyPoint to_cv(const Keypoint& k) {
    cv::KeyPoint c(static_cast<float>(k.column), static_cast<float>(k.row), k.size, k.angle,
                   k.response, k.octave, k.class_id);
    return c;
}

Keypoint from_cv(const cv::KeyPoint& c) {
    return {c.pt.y, c.pt.x, c.size, c.angle, c.response, c.octave, c.class_id};
}

}  // namespace

Raster8 prepared_image(const Raster8& image, const FeatureParameters& p) {
    if (!p.clahe || image.pixels.empty()) return image;
    Raster8 out = image;
    cv::Mat dst(out.rows, out.columns, CV_8UC1, out.pixels.data());
    cv::createCLAHE(p.clahe_clip_limit, cv::Size(p.clahe_tiles, p.clahe_tiles))
        ->apply(view_of(image), dst);
    return out;
}

std::vector<Keypoint> detect_keypoints(const Raster8& image, const Raster8& mask,
                                       const FeatureParameters& p) {
    validate(p);
    if (!mask.pixels.empty() && (mask.rows != image.rows || mask.columns != image.columns))
        throw Error("keypoints: the detection mask's size differs from the image's");
    // The detector works on the mask's bounding rectangle only, widened by a margin that
    // covers its largest filters (KAZE's coarsest scale, σ ≈ 1.6 · 2^octaves pixels), so a
    // mask confined to the zones of interest saves the scale space of the rest.
    cv::Rect roi(0, 0, image.columns, image.rows);
    if (!mask.pixels.empty()) {
        int top = image.rows, bottom = -1, left = image.columns, right = -1;
        for (int r = 0; r < mask.rows; ++r)
            for (int c = 0; c < mask.columns; ++c)
                if (mask.at(r, c)) {
                    top = std::min(top, r);
                    bottom = std::max(bottom, r);
                    left = std::min(left, c);
                    right = std::max(right, c);
                }
        if (bottom < 0) return {};
        const int margin = 64;
        roi = cv::Rect(cv::Point(std::max(left - margin, 0), std::max(top - margin, 0)),
                       cv::Point(std::min(right + margin + 1, image.columns),
                                 std::min(bottom + margin + 1, image.rows)));
    }
    std::vector<cv::KeyPoint> found;
    try {
        create(p.detector, p, true)
            ->detect(view_of(image)(roi), found,
                     mask.pixels.empty() ? cv::Mat() : view_of(mask)(roi));
    } catch (const cv::Exception& e) {
        throw Error("keypoints: the '" + p.detector + "' detector failed: " + e.what());
    }
    for (auto& k : found) k.pt += cv::Point2f(static_cast<float>(roi.x), static_cast<float>(roi.y));
    if (p.max_keypoints > 0) cv::KeyPointsFilter::retainBest(found, p.max_keypoints);
    std::vector<Keypoint> out;
    out.reserve(found.size());
    for (const auto& c : found) out.push_back(from_cv(c));
    return out;
}

Features describe_keypoints(const Raster8& image, const std::vector<Keypoint>& keypoints,
                            const FeatureParameters& p) {
    validate(p);
    const bool own = p.descriptor == p.detector;
    std::vector<cv::KeyPoint> cv_keypoints;
    cv_keypoints.reserve(keypoints.size());
    for (std::size_t i = 0; i < keypoints.size(); ++i) {
        cv::KeyPoint c = to_cv(keypoints[i]);
        if (!own) {
            // Another family's descriptor: SIFT's packed octave (octave | layer << 8) would
            // be misread as a scale, and the keypoint's index goes in class_id so that the
            // survivors can be traced back after the descriptor drops some.
            c.octave = 0;
            c.class_id = static_cast<int>(i);
        }
        cv_keypoints.push_back(c);
    }
    cv::Mat d;
    try {
        create(p.descriptor, p, false)->compute(view_of(image), cv_keypoints, d);
    } catch (const cv::Exception& e) {
        throw Error("keypoints: the '" + p.descriptor + "' descriptor failed: " + e.what());
    }
    Features out;
    if (static_cast<std::size_t>(d.rows) != cv_keypoints.size())
        throw Error("keypoints: the '" + p.descriptor + "' descriptor returned " +
                    std::to_string(d.rows) + " descriptors for " +
                    std::to_string(cv_keypoints.size()) + " keypoints");
    out.keypoints.reserve(cv_keypoints.size());
    for (const auto& c : cv_keypoints) {
        if (own) {
            out.keypoints.push_back(from_cv(c));
            continue;
        }
        if (c.class_id < 0 || static_cast<std::size_t>(c.class_id) >= keypoints.size())
            throw Error("keypoints: the '" + p.descriptor + "' descriptor lost a keypoint's index");
        Keypoint k = keypoints[static_cast<std::size_t>(c.class_id)];
        k.angle = c.angle;  // the orientation the descriptor was computed at
        out.keypoints.push_back(k);
    }
    out.descriptors.binary = d.depth() == CV_8U;
    if (!out.descriptors.binary && d.depth() != CV_32F)
        throw Error("keypoints: the '" + p.descriptor + "' descriptor has an unexpected type");
    out.descriptors.length = static_cast<std::size_t>(d.cols);
    const std::size_t n = static_cast<std::size_t>(d.rows) * static_cast<std::size_t>(d.cols);
    if (d.rows > 0) {
        const cv::Mat c = d.isContinuous() ? d : d.clone();
        if (out.descriptors.binary)
            out.descriptors.bits.assign(c.ptr<std::uint8_t>(0), c.ptr<std::uint8_t>(0) + n);
        else
            out.descriptors.values.assign(c.ptr<float>(0), c.ptr<float>(0) + n);
    }
    return out;
}

RasterRgb draw_matches(const Raster8& image, const std::vector<DrawnMatch>& matches,
                       double vector_scale) {
    cv::Mat colour;
    cv::cvtColor(view_of(image), colour, cv::COLOR_GRAY2RGB);
    constexpr int shift = 4;  // sub-pixel drawing: coordinates in 1/16 pixel
    auto point = [](double row, double column) {
        return cv::Point(static_cast<int>(std::lround(column * (1 << shift))),
                         static_cast<int>(std::lround(row * (1 << shift))));
    };
    for (int pass = 0; pass < 2; ++pass) {  // the removed first, the kept drawn over them
        for (const auto& m : matches) {
            if (m.kept != (pass == 1)) continue;
            const cv::Scalar colour_of = m.kept ? cv::Scalar(0, 200, 0) : cv::Scalar(255, 0, 0);
            const cv::Point from = point(m.row, m.column);
            const cv::Point to = point(m.row + vector_scale * (m.to_row - m.row),
                                       m.column + vector_scale * (m.to_column - m.column));
            cv::circle(colour, from, 3 << shift, colour_of, 1, cv::LINE_AA, shift);
            cv::line(colour, from, to, colour_of, 1, cv::LINE_AA, shift);
        }
    }
    RasterRgb out{colour.rows, colour.cols, {}};
    out.pixels.assign(colour.datastart, colour.dataend);  // continuous, 3 bytes a pixel
    return out;
}

}  // namespace tlsmon::keypoints
