// `tlsmon keypoints REFERENCE EPOCH ... --out VECTORS.csv`: the keypoint displacement
// method (docs/keypoints.md) between two structured scans, measured by the keypoint stage
// itself (pipeline/keypoint_stage.hpp: its reference product, its measurement with the patch
// refinement, its segments and outlier filters). The parameters start from a fresh site's
// defaults (algorithms/keypoints/parameters.hpp) with bands of the vertical angle as
// segments, or from the site's [keypoints] and zones with --config, which also registers
// EPOCH onto REFERENCE as the daemon does (cli/file_pair.hpp); each option given replaces
// one. One CSV row per match of each segment, a summary per segment, and on request the
// intensity images with the matches drawn.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "algorithms/keypoints/opencv_features.hpp"
#include "algorithms/keypoints/spherical_image.hpp"
#include "cli/commands.hpp"
#include "cli/file_pair.hpp"
#include "cli/result_file.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/fixed_decimals.hpp"
#include "formats/png_file.hpp"
#include "pipeline/keypoint_stage.hpp"

namespace tlsmon {

namespace {

using namespace keypoints;

KeypointConfig parameters_of(const KeypointsOptions& o, const std::optional<Config>& site) {
    KeypointConfig p;
    if (site) {
        p = pipeline_config(*site).keypoints;
    } else {
        p.segments = KeypointSegments::bands;  // no zones without a site
    }
    if (o.detector) p.detector = *o.detector;
    if (o.descriptor) p.descriptor = *o.descriptor;
    if (o.detector_threshold) p.detector_threshold = *o.detector_threshold;
    if (o.window_deg) p.window_deg = *o.window_deg;
    if (o.window_m) p.window_m = *o.window_m;
    if (o.ratio) p.ratio = *o.ratio;
    if (o.mutual) p.mutual = true;
    if (o.clahe) p.clahe = true;
    if (o.no_refine) p.refine = false;
    if (o.segments_deg) {
        p.segments = KeypointSegments::bands;
        p.band_width_deg = *o.segments_deg;
    }
    return p;
}

void require_structured(const std::vector<Scan>& scans, const std::string& path) {
    for (const auto& scan : scans)
        if (scan.grid) return;
    throw Error(path +
                ": no structured scan (a grid of rows and columns, as PTX or a gridded E57 "
                "has): keypoints need the scanner's spherical images");
}

// Only the k-th structured scan of the file (from 1), when --scan asks for one.
std::shared_ptr<const std::vector<Scan>> only_scan(std::shared_ptr<const std::vector<Scan>> scans,
                                                   const std::optional<int>& k,
                                                   const std::string& path) {
    if (!k) return scans;
    int found = 0;
    for (const auto& scan : *scans)
        if (scan.grid && ++found == *k) return std::make_shared<const std::vector<Scan>>(1, scan);
    throw Error(path + ": holds " + std::to_string(found) + " structured scan(s), not " +
                std::to_string(*k) + " (--scan)");
}

// `segment`: the band's index for bands, the zone's position in the configuration for zones.
void write_csv(const std::string& path, const KeypointSegmentsResult& segments, bool bands) {
    ResultFile f(path);
    f.write(
        "reference_row_px,reference_column_px,row_px,column_px,x_m,y_m,z_m,dx_m,dy_m,dz_m,"
        "descriptor_distance,segment,zone,removed_by\n");
    for (std::size_t s = 0; s < segments.segments.size(); ++s) {
        const KeypointSegmentResult& seg = segments.segments[s];
        for (std::size_t i = 0; i < seg.matches.size(); ++i) {
            const KeypointMatch& m = seg.matches[i];
            const Eigen::Vector3d d = m.displacement();
            const OutlierFilter removed = seg.removed_by[i];
            const std::string row = csv_line(std::vector<std::string>{
                csv_number(m.reference_row), csv_number(m.reference_column), csv_number(m.row),
                csv_number(m.column), csv_number(m.reference_point.x()),
                csv_number(m.reference_point.y()), csv_number(m.reference_point.z()),
                csv_number(d.x()), csv_number(d.y()), csv_number(d.z()),
                csv_number(m.descriptor_distance),
                std::to_string(bands ? seg.displacement.segment : int(s)), seg.zone,
                removed == OutlierFilter::none ? std::string()
                                               : std::string(outlier_filter_name(removed))});
            f.write(row);
        }
    }
    f.close();
}

// One row per segment at full precision (metres): the figures the stage stores, the standard
// errors beside them, and the share of the zone's area they stand for (zone_strata.hpp).
void write_summary(const std::string& path, const KeypointSegmentsResult& segments) {
    std::ofstream f(path);
    if (!f) throw Error(path + ": cannot write: " + std::strerror(errno));
    f << "zone,matches,kept,dx_m,dy_m,dz_m,se_dx_m,se_dy_m,se_dz_m,normal_m,surface_h_m,"
         "surface_v_m,se_normal_m,se_surface_h_m,se_surface_v_m,covered_area_share,undefined\n";
    const auto field = [](double v) { return std::isfinite(v) ? csv_number(v) : std::string(); };
    for (const auto& s : segments.segments) {
        const SegmentDisplacement& d = s.displacement;
        std::vector<std::string> row{s.zone, std::to_string(d.matches), std::to_string(d.count)};
        for (const Eigen::Vector3d* v :
             {&d.mean, &d.standard_error, &d.along, &d.along_standard_error})
            for (int k = 0; k < 3; ++k) row.push_back(field((*v)(k)));
        row.push_back(field(d.covered_area_share));
        row.push_back(d.undefined_reason);
        f << csv_line(row);
    }
    if (!f.flush()) throw Error(path + ": write failed: " + std::strerror(errno));
}

// Per segment (docs/keypoints.md, step 6): matches and kept, the mean vector and its spread,
// the components along the wall's normal and along the surface, their LoD95.
void print_summary(const KeypointSegmentsResult& segments) {
    std::cout << "zone  matches  kept  dx_mm  dy_mm  dz_mm  sx_mm  sy_mm  sz_mm  normal_mm  "
                 "surface_h_mm  surface_v_mm  (or why undefined)\n";
    for (const auto& s : segments.segments) {
        const SegmentDisplacement& d = s.displacement;
        std::cout << s.zone << "  " << d.matches << "  " << d.count;
        if (!d.defined()) {
            std::cout << "  " << d.undefined_reason << "\n";
            continue;
        }
        for (int k = 0; k < 3; ++k) std::cout << "  " << fixed_decimals(1000 * d.mean(k), 2);
        for (int k = 0; k < 3; ++k) std::cout << "  " << fixed_decimals(1000 * d.std_dev(k), 2);
        for (int k = 0; k < 3; ++k) std::cout << "  " << fixed_decimals(1000 * d.along(k), 2);
        if (!d.wall.defined()) std::cout << "  (wall frame: " << d.wall.undefined_reason << ")";
        std::cout << "\n";
    }
}

// The first structured scan's intensity image as the detector saw it, with the matches of
// that scan drawn (on the epoch's, each vector points back to where the keypoint was).
void write_pictures(const std::string& folder, const KeypointConfig& p, const FilePair& pair,
                    const KeypointSegmentsResult& segments, double vector_scale) {
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) throw Error(folder + ": cannot create the folder: " + ec.message());
    const FeatureParameters features = features_of(p);
    const auto grey = [&](const std::vector<Scan>& scans) {
        for (const auto& s : scans)
            if (s.grid)
                return prepared_image(intensity_to_8bit(spherical_images_from_grid(s)), features);
        throw Error("no structured scan to draw");
    };
    std::vector<DrawnMatch> on_reference, on_epoch;
    for (const auto& s : segments.segments) {
        for (std::size_t i = 0; i < s.matches.size(); ++i) {
            const KeypointMatch& m = s.matches[i];
            if (m.scan != 0) continue;
            const bool kept = s.removed_by[i] == OutlierFilter::none;
            on_reference.push_back({m.reference_row, m.reference_column, m.row, m.column, kept});
            on_epoch.push_back({m.row, m.column, m.reference_row, m.reference_column, kept});
        }
    }
    const auto write = [&](const char* name, const Raster8& image,
                           const std::vector<DrawnMatch>& drawn) {
        const RasterRgb picture = draw_matches(image, drawn, vector_scale);
        write_png_rgb(std::filesystem::path(folder) / name, picture.rows, picture.columns,
                      picture.pixels);
    };
    write("reference.png", grey(*pair.reference_scans), on_reference);
    write("epoch.png", grey(*pair.epoch_scans), on_epoch);
}

}  // namespace

int run_keypoints(const KeypointsOptions& o) {
    try {
        const std::optional<Config> site = site_config(o.config);
        const KeypointConfig p = parameters_of(o, site);
        validate(features_of(p));  // before reading two scans, not after
        Config shown = site.value_or(Config{});
        static_cast<keypoints::Parameters&>(shown.keypoints) = p;
        shown.keypoints.segments = p.segments;
        std::cout << effective_parameters(shown, "keypoints");

        FilePair pair = read_file_pair(o.reference, o.epoch, site);
        require_structured(*pair.reference_scans, o.reference);
        require_structured(*pair.epoch_scans, o.epoch);
        pair.reference_scans = only_scan(pair.reference_scans, o.scan, o.reference);
        pair.epoch_scans = only_scan(pair.epoch_scans, o.scan, o.epoch);
        std::cout << "registration: " << pair.registration << "\n";

        // The stage's two halves: its reference product, then the epoch measured against it.
        const KeypointStage stage(p);
        const KeypointReference reference = stage.prepare_reference(*pair.reference_scans);
        KeypointEpoch epoch = measure_keypoints(p, reference, *pair.epoch_scans, pair.outputs);
        const std::size_t in_3d = epoch.matches.size();
        const KeypointSegmentsResult segments =
            keypoint_segments(p, reference, std::move(epoch.matches), pair.outputs);
        write_csv(o.out, segments, p.segments == KeypointSegments::bands);
        if (!o.summary.empty()) write_summary(o.summary, segments);
        if (!o.images.empty()) write_pictures(o.images, p, pair, segments, o.vector_scale);

        std::cout << p.detector << " + " << p.descriptor << ": reference " << reference.keypoints()
                  << " keypoints in " << reference.scans.size() << " scan(s); epoch "
                  << epoch.described << " described, " << epoch.pairs << " matched within "
                  << p.window_deg << " deg (at least " << p.window_m << " m at the object), "
                  << epoch.dropped_patch << " without their patch, " << in_3d << " in 3-D -> "
                  << o.out << "\n";
        std::cout << "epoch steps, s: images " << fixed_decimals(epoch.images_s, 2)
                  << ", detection " << fixed_decimals(epoch.detection_s, 2) << ", description "
                  << fixed_decimals(epoch.description_s, 2) << ", matching "
                  << fixed_decimals(epoch.matching_s, 2) << ", 3-D "
                  << fixed_decimals(epoch.to_3d_s, 2) << ", filtering "
                  << fixed_decimals(segments.filtering_s, 2) << "\n";
        print_summary(segments);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon keypoints: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
