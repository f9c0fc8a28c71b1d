// One epoch's keypoint analysis against a reference (issue 12: < 10 s on 2 cores), step by
// step: spherical images, detection, description, matching, 3-D. The reference's images,
// keypoints and descriptors are prepared first and not counted (the pipeline computes them
// once and keeps them in the reference cache); reading the files is not counted either.
//
//   bench_keypoints REFERENCE EPOCH [DETECTOR DESCRIPTOR [WINDOW_DEG [RATIO [MUTUAL
//                   [OCTAVES LAYERS [BOX...]]]]]]
// BOX: xmin,ymin,zmin,xmax,ymax,zmax in the project frame; when given, detection is confined
// to the returns inside the boxes (the zones of interest), as the pipeline's stage does.
//
// e.g. two epochs of `tlsmon simulate --preset pier --epochs 2 --out /tmp/pier`.
// OpenCV's own threads are left at their default (every core: 2 on the bench machine).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "algorithms/keypoints/keypoint_matching.hpp"
#include "algorithms/keypoints/keypoint_to_3d.hpp"
#include "algorithms/keypoints/opencv_features.hpp"
#include "algorithms/keypoints/spherical_image.hpp"
#include "bench/bench_support.hpp"
#include "formats/scan_file.hpp"

namespace {

using namespace tlsmon;
using namespace tlsmon::keypoints;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
    return bench::seconds_since(t0);
}
double process_cpu() {
    return bench::process_cpu_seconds();
}

Scan read_structured(const char* path) {
    auto scans = read_scans(path);
    for (auto& s : scans)
        if (s.grid) return std::move(s);
    std::fprintf(stderr, "%s: no structured scan\n", path);
    std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: bench_keypoints REFERENCE EPOCH [DETECTOR DESCRIPTOR [WINDOW_DEG "
                     "[RATIO [MUTUAL]]]]\n");
        return 2;
    }
    FeatureParameters features;
    if (argc > 4) {
        features.detector = argv[3];
        features.descriptor = argv[4];
    }
    MatchingParameters matching;
    if (argc > 5) matching.window_radius = std::atof(argv[5]) * std::numbers::pi / 180.0;
    if (argc > 6) matching.ratio = std::atof(argv[6]);
    if (argc > 7) matching.mutual = std::atoi(argv[7]) != 0;
    if (argc > 9) {
        features.kaze_octaves = std::atoi(argv[8]);
        features.kaze_octave_layers = std::atoi(argv[9]);
    }
    constexpr int margin = 2;
    std::vector<Eigen::AlignedBox3d> boxes;
    for (int i = 10; i < argc; ++i) {
        double v[6];
        if (std::sscanf(argv[i], "%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                        &v[5]) != 6) {
            std::fprintf(stderr, "%s: not a box xmin,ymin,zmin,xmax,ymax,zmax\n", argv[i]);
            return 2;
        }
        boxes.emplace_back(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]));
    }
    const auto mask_of = [&](const SphericalImages& images) {
        Raster8 mask = detection_mask(images, margin);
        if (!boxes.empty()) restrict_mask(mask, pixels_in_boxes(images, boxes));
        return mask;
    };

    auto t0 = Clock::now();
    const Scan reference_scan = read_structured(argv[1]);
    const Scan epoch_scan = read_structured(argv[2]);
    std::printf("read both files: %.2f s (not counted)\n", since(t0));

    t0 = Clock::now();
    const SphericalImages reference = spherical_images_from_grid(reference_scan);
    const Raster8 reference_grey = prepared_image(intensity_to_8bit(reference), features);
    const auto reference_keypoints = detect_keypoints(reference_grey, mask_of(reference), features);
    const Features reference_features =
        describe_keypoints(reference_grey, reference_keypoints, features);
    const auto reference_positions = angular_positions(reference, reference_features.keypoints);
    std::printf(
        "reference %lld x %lld pixels, %zu keypoints, %zu described: %.2f s (cached, "
        "not counted)\n",
        static_cast<long long>(reference.rows), static_cast<long long>(reference.columns),
        reference_keypoints.size(), reference_features.keypoints.size(), since(t0));

    const auto start = Clock::now();
    t0 = Clock::now();
    double c0 = process_cpu();
    const SphericalImages epoch = spherical_images_from_grid(epoch_scan);
    const Raster8 grey = prepared_image(intensity_to_8bit(epoch), features);
    const Raster8 mask = mask_of(epoch);
    const double t_images = since(t0);
    const double cpu_images = process_cpu() - c0;
    c0 = process_cpu();
    t0 = Clock::now();
    const auto keypoints = detect_keypoints(grey, mask, features);
    const double t_detect = since(t0);
    const double cpu_detect = process_cpu() - c0;
    c0 = process_cpu();
    t0 = Clock::now();
    const Features described = describe_keypoints(grey, keypoints, features);
    const double t_describe = since(t0);
    const double cpu_describe = process_cpu() - c0;
    c0 = process_cpu();
    t0 = Clock::now();
    const auto pairs = match_keypoints(reference_positions, reference_features.descriptors,
                                       angular_positions(epoch, described.keypoints),
                                       described.descriptors, matching);
    const double t_match = since(t0);
    const double cpu_match = process_cpu() - c0;
    c0 = process_cpu();
    t0 = Clock::now();
    const auto in_3d = matches_to_3d(reference, reference_features.keypoints, reference.pose, epoch,
                                     described.keypoints, epoch.pose, pairs);
    const double t_3d = since(t0);
    const double cpu_3d = process_cpu() - c0;
    c0 = process_cpu();
    const double total = since(start);

    std::vector<double> lengths;
    for (const auto& m : in_3d.matches) lengths.push_back(m.displacement().norm());
    std::sort(lengths.begin(), lengths.end());
    const double median_mm = lengths.empty() ? NAN : 1000 * lengths[lengths.size() / 2];

    std::printf("%s + %s (octaves %d x %d), window %.3f deg, ratio %.2f, mutual %d\n",
                features.detector.c_str(), features.descriptor.c_str(), features.kaze_octaves,
                features.kaze_octave_layers, matching.window_radius * 180 / std::numbers::pi,
                matching.ratio, int(matching.mutual));
    std::printf("step         wall s   cpu s\n");
    std::printf("images       %6.2f  %6.2f\n", t_images, cpu_images);
    std::printf("detection    %6.2f  %6.2f  (%zu keypoints)\n", t_detect, cpu_detect,
                keypoints.size());
    std::printf("description  %6.2f  %6.2f  (%zu described)\n", t_describe, cpu_describe,
                described.keypoints.size());
    std::printf("matching     %6.2f  %6.2f  (%zu pairs)\n", t_match, cpu_match, pairs.size());
    std::printf(
        "3-D          %6.2f  %6.2f  (%zu in 3-D; dropped: %zu outside, %zu empty "
        "neighbour, %zu depth edge)\n",
        t_3d, cpu_3d, in_3d.matches.size(), in_3d.dropped_outside, in_3d.dropped_empty_neighbour,
        in_3d.dropped_depth_edge);
    std::printf("total        %6.2f  %6.2f  (filtering: not yet, the outlier filters' own)\n",
                total, cpu_images + cpu_detect + cpu_describe + cpu_match + cpu_3d);
    std::printf("median |vector| %.2f mm\n", median_mm);
    return 0;
}
