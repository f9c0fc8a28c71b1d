// `tlsmon keypoints REFERENCE EPOCH ... --out VECTORS.csv`: the keypoint displacement
// method (docs/keypoints.md) between two structured scans already in one frame, as an
// analyst runs it by hand: spherical images, keypoints, matching in an angular window, 3-D,
// outlier filters, one CSV row per match and a summary per segment (bands of the
// reference's vertical angle).
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "algorithms/keypoints/keypoint_match.hpp"
#include "algorithms/keypoints/keypoint_matching.hpp"
#include "algorithms/keypoints/keypoint_to_3d.hpp"
#include "algorithms/keypoints/opencv_features.hpp"
#include "algorithms/keypoints/outlier_filters.hpp"
#include "algorithms/keypoints/segment_displacement.hpp"
#include "algorithms/keypoints/spherical_image.hpp"
#include "core/error.hpp"
#include "daemon/commands.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon {

namespace {

using namespace keypoints;
using Clock = std::chrono::steady_clock;
constexpr double deg = std::numbers::pi / 180.0;
constexpr int mask_margin = 2;  // pixels kept between a keypoint and an empty pixel

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The k-th structured scan of the file (from 1).
Scan read_structured(const std::string& path, int k) {
    int found = 0;
    for (auto& scan : read_scans(path))
        if (scan.grid && ++found == k) return std::move(scan);
    if (found > 0) {
        throw Error(path + ": holds " + std::to_string(found) + " structured scan(s), not " +
                    std::to_string(k) + " (--scan)");
    }
    throw Error(path +
                ": no structured scan (a grid of rows and columns, as PTX or a gridded "
                "E57 has): keypoints need the scanner's spherical images");
}

struct Prepared {
    SphericalImages images;
    Raster8 grey;
    Features features;
    std::vector<AngularPosition> positions;
    std::size_t detected = 0;
    double images_s = 0, detection_s = 0, description_s = 0;
};

Prepared prepare(const Scan& scan, const FeatureParameters& parameters) {
    Prepared p;
    auto t0 = Clock::now();
    p.images = spherical_images_from_grid(scan);
    p.grey = prepared_image(intensity_to_8bit(p.images), parameters);
    const Raster8 mask = detection_mask(p.images, mask_margin);
    p.images_s = since(t0);
    t0 = Clock::now();
    const auto keypoints = detect_keypoints(p.grey, mask, parameters);
    p.detected = keypoints.size();
    p.detection_s = since(t0);
    t0 = Clock::now();
    p.features = describe_keypoints(p.grey, keypoints, parameters);
    p.description_s = since(t0);
    p.positions = angular_positions(p.images, p.features.keypoints);
    return p;
}

// Each match's `removed_by`: the outlier filter that removed it (Hochmoselbrücke method,
// step 5: algorithms/keypoints/outlier_filters.hpp), empty when kept.
std::vector<std::string> removed_by_names(const std::vector<OutlierFilter>& removed_by) {
    std::vector<std::string> names;
    names.reserve(removed_by.size());
    for (const auto f : removed_by)
        names.emplace_back(f == OutlierFilter::none ? std::string_view{} : outlier_filter_name(f));
    return names;
}

// "nan" for NaN, else the number with `decimals` decimals.
std::string number(double v, int decimals) {
    if (std::isnan(v)) return "nan";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

void write_csv(const std::string& path, const std::vector<KeypointMatch>& matches,
               const std::vector<std::string>& removed_by) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw Error(path + ": cannot write: " + std::strerror(errno));
    std::fputs(
        "reference_row,reference_column,row,column,x,y,z,dx,dy,dz,descriptor_distance,segment,"
        "removed_by\n",
        f);
    for (std::size_t i = 0; i < matches.size(); ++i) {
        const KeypointMatch& m = matches[i];
        const Eigen::Vector3d d = m.displacement();
        const std::string row =
            number(m.reference_row, 3) + ',' + number(m.reference_column, 3) + ',' +
            number(m.row, 3) + ',' + number(m.column, 3) + ',' + number(m.reference_point.x(), 6) +
            ',' + number(m.reference_point.y(), 6) + ',' + number(m.reference_point.z(), 6) + ',' +
            number(d.x(), 6) + ',' + number(d.y(), 6) + ',' + number(d.z(), 6) + ',' +
            number(m.descriptor_distance, 3) + ',' + std::to_string(m.segment) + ',' +
            removed_by[i] + '\n';
        std::fputs(row.c_str(), f);
    }
    const bool failed = std::ferror(f) != 0;
    if (std::fclose(f) != 0 || failed)
        throw Error(path + ": write failed: " + std::strerror(errno));
}

// Per segment (step 6: algorithms/keypoints/segment_displacement.hpp): the matches kept,
// the mean vector and its spread, and the components along the wall's normal (fitted to the
// kept reference points, oriented towards the scanner) and along the surface.
void print_summary(const std::vector<KeypointMatch>& matches,
                   const std::vector<OutlierFilter>& removed_by, double width,
                   const Eigen::Vector3d& scanner) {
    std::vector<int> segments;
    for (const auto& m : matches) segments.push_back(m.segment);
    std::sort(segments.begin(), segments.end());
    segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
    SegmentParameters parameters;
    parameters.orientation = m3c2::Orientation::towards(scanner);
    std::cout << "segment  elevation_deg  matches  kept  dx_mm  dy_mm  dz_mm  sx_mm  sy_mm  "
                 "sz_mm  normal_mm  surface_h_mm  surface_v_mm  (or why undefined)\n";
    for (const int segment : segments) {
        const SegmentDisplacement d =
            segment_displacement(matches, removed_by, segment, parameters);
        const auto [lo, hi] = vertical_angle_band_bounds(segment, width);
        std::cout << segment << "  " << number(lo / deg, 1) << ".." << number(hi / deg, 1) << "  "
                  << d.matches << "  " << d.count;
        if (!d.defined()) {
            std::cout << "  " << d.undefined_reason << "\n";
            continue;
        }
        for (int k = 0; k < 3; ++k) std::cout << "  " << number(1000 * d.mean(k), 2);
        for (int k = 0; k < 3; ++k) std::cout << "  " << number(1000 * d.std_dev(k), 2);
        for (int k = 0; k < 3; ++k) std::cout << "  " << number(1000 * d.along(k), 2);
        if (!d.wall.defined()) std::cout << "  (wall frame: " << d.wall.undefined_reason << ")";
        std::cout << "\n";
    }
}

void write_pictures(const std::string& folder, const Prepared& reference, const Prepared& epoch,
                    const std::vector<KeypointMatch>& matches,
                    const std::vector<std::string>& removed_by, double vector_scale) {
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) throw Error(folder + ": cannot create the folder: " + ec.message());
    std::vector<DrawnMatch> on_reference, on_epoch;
    for (std::size_t i = 0; i < matches.size(); ++i) {
        const KeypointMatch& m = matches[i];
        const bool kept = removed_by[i].empty();
        on_reference.push_back({m.reference_row, m.reference_column, m.row, m.column, kept});
        // On the epoch's image, the vector points back to where the keypoint was.
        on_epoch.push_back({m.row, m.column, m.reference_row, m.reference_column, kept});
    }
    write_match_picture((std::filesystem::path(folder) / "reference.png").string(), reference.grey,
                        on_reference, vector_scale);
    write_match_picture((std::filesystem::path(folder) / "epoch.png").string(), epoch.grey,
                        on_epoch, vector_scale);
}

}  // namespace

int run_keypoints(const KeypointsOptions& o) {
    try {
        FeatureParameters features;
        features.detector = o.detector;
        features.descriptor = o.descriptor;
        features.clahe = o.clahe;
        validate(features);  // before reading two scans, not after
        MatchingParameters matching;
        matching.window_radius = o.window_deg * deg;
        matching.ratio = o.ratio;
        matching.mutual = o.mutual;

        const Prepared reference = prepare(read_structured(o.reference, o.scan), features);
        const Prepared epoch = prepare(read_structured(o.epoch, o.scan), features);
        auto t0 = Clock::now();
        const auto pairs = match_keypoints(reference.positions, reference.features.descriptors,
                                           epoch.positions, epoch.features.descriptors, matching);
        const double matching_s = since(t0);
        t0 = Clock::now();
        // Both scans in their own files' frame (scanner -> project: the pose as read).
        MatchesIn3d in3d =
            matches_to_3d(reference.images, reference.features.keypoints, reference.images.pose,
                          epoch.images, epoch.features.keypoints, epoch.images.pose, pairs);
        const double to_3d_s = since(t0);
        const double width = o.segments_deg * deg;
        for (auto& m : in3d.matches) m.segment = vertical_angle_band(m.reference_elevation, width);
        const OutlierResult filtered = filter_outliers(in3d.matches);
        const auto removed_by = removed_by_names(filtered.removed_by);
        write_csv(o.out, in3d.matches, removed_by);
        if (!o.images.empty())
            write_pictures(o.images, reference, epoch, in3d.matches, removed_by, o.vector_scale);

        std::cout << features.detector << " + " << features.descriptor << ": reference "
                  << reference.images.rows << " x " << reference.images.columns << " pixels, "
                  << reference.features.keypoints.size() << " keypoints described; epoch "
                  << epoch.features.keypoints.size() << "; " << pairs.size() << " matched within "
                  << o.window_deg << " deg; " << in3d.matches.size()
                  << " in 3-D (dropped: " << in3d.dropped_empty_neighbour << " empty neighbour, "
                  << in3d.dropped_depth_edge << " depth edge, " << in3d.dropped_outside
                  << " outside) -> " << o.out << "\n";
        std::cout << "epoch steps, s: images " << number(epoch.images_s, 2) << ", detection "
                  << number(epoch.detection_s, 2) << ", description "
                  << number(epoch.description_s, 2) << ", matching " << number(matching_s, 2)
                  << ", 3-D " << number(to_3d_s, 2) << "\n";
        print_summary(in3d.matches, filtered.removed_by, width,
                      reference.images.pose.translation());
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon keypoints: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
