#include "pipeline/keypoint_stage.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <span>

#include "algorithms/keypoints/keypoint_to_3d.hpp"
#include "algorithms/keypoints/opencv_features.hpp"
#include "algorithms/keypoints/patch_refinement.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "core/error.hpp"
#include "core/payload.hpp"
#include "pipeline/keypoint_results.hpp"
#include "pipeline/m3c2_stage.hpp"

namespace tlsmon {

namespace {

using namespace keypoints;
using Clock = std::chrono::steady_clock;

constexpr double kDeg = std::numbers::pi / 180.0;
// Pixels kept between a keypoint and an empty pixel (spherical_image.hpp, detection_mask).
constexpr int kMaskMargin = 2;
// Zone boxes grown by this before they confine detection: an epoch's scan lies in its file's
// frame, a few centimetres from the reference's before registration.
constexpr double kBoxMargin = 0.25;  // m

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

FeatureParameters feature_parameters(const KeypointConfig& c) {
    FeatureParameters f;
    f.detector = c.detector;
    f.descriptor = c.descriptor;
    f.clahe = c.clahe;
    return f;
}

const Scan& structured_scan(const std::vector<Scan>& scans, const char* which) {
    for (const auto& s : scans)
        if (s.grid) return s;
    throw Error(std::string("keypoints: the ") + which +
                " holds no structured scan (a grid of rows and columns, as PTX or a gridded "
                "E57 has): the method needs the scanner's spherical images");
}

// The detection mask: valid pixels away from holes, inside the zones when they are the
// segments (detection then works on their bounding rectangle only).
Raster8 mask_for(const KeypointConfig& c, const SphericalImages& images) {
    Raster8 mask = detection_mask(images, kMaskMargin);
    if (c.segments == KeypointSegments::zones) {
        std::vector<Eigen::AlignedBox3d> boxes;
        for (const auto& z : c.zones) {
            Eigen::AlignedBox3d b = z.bounds();
            b.min().array() -= kBoxMargin;
            b.max().array() += kBoxMargin;
            boxes.push_back(b);
        }
        restrict_mask(mask, pixels_in_boxes(images, boxes));
    }
    return mask;
}

// Features detected and described in one scan's images.
struct Described {
    SphericalImages images;
    Features features;
    std::vector<AngularPosition> positions;
    std::size_t detected = 0;
    double images_s = 0, detection_s = 0, description_s = 0;
};

Described describe_scan(const KeypointConfig& c, const Scan& scan) {
    const FeatureParameters fp = feature_parameters(c);
    Described d;
    auto t0 = Clock::now();
    d.images = spherical_images_from_grid(scan);
    const Raster8 grey = prepared_image(intensity_to_8bit(d.images), fp);
    const Raster8 mask = mask_for(c, d.images);
    d.images_s = since(t0);
    t0 = Clock::now();
    const auto found = detect_keypoints(grey, mask, fp);
    d.detected = found.size();
    d.detection_s = since(t0);
    t0 = Clock::now();
    d.features = describe_keypoints(grey, found, fp);
    d.description_s = since(t0);
    d.positions = angular_positions(d.images, d.features.keypoints);
    return d;
}

void put_vector(PayloadWriter& w, const Eigen::Vector3d& v) {
    w.put<double>(v.x());
    w.put<double>(v.y());
    w.put<double>(v.z());
}

Eigen::Vector3d get_vector(PayloadReader& r) {
    Eigen::Vector3d v;
    v.x() = r.get<double>();
    v.y() = r.get<double>();
    v.z() = r.get<double>();
    return v;
}

void put_text(PayloadWriter& w, const std::string& s) {
    w.put_array(std::vector<char>(s.begin(), s.end()));
}

std::string get_text(PayloadReader& r) {
    const auto v = r.get_array<char>();
    return std::string(v.begin(), v.end());
}

// The registration's σ at a project-frame point in its worst direction: √ of the largest
// eigenvalue of Σ_p = J·Σ·Jᵀ (registration_error.hpp; Niemeier 2008, §2.4). A segment's
// components lie along three directions; one σ bounds each of them.
double registration_sigma_at(const registration::RigidTransform& T, const Eigen::Vector3d& q) {
    const Eigen::Vector3d x = T.rotation.transpose() * (q - T.translation) / T.scale;
    const Eigen::Matrix3d S = registration::registration_covariance_at(T, x);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(S, Eigen::EigenvaluesOnly);
    return std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
}

}  // namespace

std::string keypoint_reference_parameters(const KeypointConfig& c) {
    std::string s = fmt::format("detector={};descriptor={};clahe={};segments={};patch={}",
                                c.detector, c.descriptor, c.clahe ? 1 : 0,
                                c.segments == KeypointSegments::zones ? "zones" : "bands",
                                c.refine ? c.patch_radius : 0);
    if (c.segments == KeypointSegments::zones) {
        for (const auto& z : c.zones) {
            s += fmt::format(";zone={}:{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", z.name,
                             z.box.min().x(), z.box.min().y(), z.box.min().z(), z.box.max().x(),
                             z.box.max().y(), z.box.max().z());
            for (const auto& v : z.polygon) s += fmt::format(":{:.17g},{:.17g}", v.x(), v.y());
        }
    }
    return s;
}

KeypointReference prepare_keypoint_reference(const KeypointConfig& config,
                                             const std::vector<Scan>& scans) {
    const auto t0 = Clock::now();
    const Scan& scan = structured_scan(scans, "reference epoch");
    Described d = describe_scan(config, scan);
    KeypointReference out;
    out.detected = d.detected;
    out.scanner = scan.scanner_position();
    out.angular_step = std::max(d.images.azimuth_step, d.images.elevation_step);
    // Only keypoints the range image can take to 3-D: the others can never give a vector.
    const auto& kp = d.features.keypoints;
    const auto& desc = d.features.descriptors;
    out.features.descriptors.binary = desc.binary;
    out.features.descriptors.length = desc.length;
    out.patch_radius = config.refine ? config.patch_radius : 0;
    for (std::size_t i = 0; i < kp.size(); ++i) {
        double row = kp[i].row, column = kp[i].column;
        PolarAt at;
        if (config.refine) {
            const int r = static_cast<int>(std::lround(row)),
                      c = static_cast<int>(std::lround(column));
            const auto patch = intensity_patch(d.images, r, c, config.patch_radius);
            if (!patch) continue;
            row = r;
            column = c;
            at = polar_at(d.images, row, column);
            if (at.dropped != Dropped::no) continue;
            out.patches.insert(out.patches.end(), patch->values.begin(), patch->values.end());
        } else {
            at = polar_at(d.images, row, column);
            if (at.dropped != Dropped::no) continue;
        }
        out.features.keypoints.push_back(kp[i]);
        if (desc.binary) {
            const auto* bits = desc.bits.data() + i * desc.length;
            out.features.descriptors.bits.insert(out.features.descriptors.bits.end(), bits,
                                                 bits + desc.length);
        } else {
            const auto* values = desc.values.data() + i * desc.length;
            out.features.descriptors.values.insert(out.features.descriptors.values.end(), values,
                                                   values + desc.length);
        }
        out.positions.push_back(d.positions[i]);
        out.anchor_rows.push_back(row);
        out.anchor_columns.push_back(column);
        out.polar.push_back(at.polar);
        out.points.push_back(d.images.pose * cartesian_of(at.polar));
    }
    if (config.segments == KeypointSegments::zones) {
        // Each zone's wall: a plane fitted to the reference's points in it (issue 12: "from a
        // plane fit to the reference points, not a constant").
        const auto towards = m3c2::Orientation::towards(out.scanner);
        for (const auto& z : config.zones) {
            std::vector<Eigen::Vector3d> inside;
            for (const auto& p : scan.xyz)
                if (p.allFinite() && z.contains(p)) inside.push_back(p);
            out.zone_names.push_back(z.name);
            out.walls.push_back(fit_wall_frame(inside, towards));
        }
    }
    out.seconds = since(t0);
    return out;
}

std::string KeypointReference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    w.put_array(features.keypoints);
    w.put<std::uint8_t>(features.descriptors.binary ? 1 : 0);
    w.put<std::uint64_t>(features.descriptors.length);
    w.put_array(features.descriptors.bits);
    w.put_array(features.descriptors.values);
    w.put_array(positions);
    w.put_array(anchor_rows);
    w.put_array(anchor_columns);
    w.put<std::int32_t>(patch_radius);
    w.put_array(patches);
    w.put_array(polar);
    std::vector<double> flat;
    flat.reserve(3 * points.size());
    for (const auto& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
    w.put_array(flat);
    put_vector(w, scanner);
    w.put<double>(angular_step);
    w.put<std::uint64_t>(detected);
    w.put<double>(seconds);
    w.put<std::uint64_t>(zone_names.size());
    for (std::size_t z = 0; z < zone_names.size(); ++z) {
        put_text(w, zone_names[z]);
        const WallFrame& f = walls[z];
        put_vector(w, f.centroid);
        put_vector(w, f.normal);
        put_vector(w, f.horizontal);
        put_vector(w, f.vertical);
        w.put<double>(f.rms);
        w.put<std::uint64_t>(f.points);
        w.put<std::uint8_t>(f.horizontal_surface ? 1 : 0);
        put_text(w, f.undefined_reason);
    }
    return w.take();
}

KeypointReference KeypointReference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion) {
        throw Error("keypoints stage payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    }
    KeypointReference r;
    r.features.keypoints = in.get_array<Keypoint>();
    r.features.descriptors.binary = in.get<std::uint8_t>() != 0;
    r.features.descriptors.length = in.get<std::uint64_t>();
    r.features.descriptors.bits = in.get_array<std::uint8_t>();
    r.features.descriptors.values = in.get_array<float>();
    r.positions = in.get_array<AngularPosition>();
    r.anchor_rows = in.get_array<double>();
    r.anchor_columns = in.get_array<double>();
    r.patch_radius = in.get<std::int32_t>();
    r.patches = in.get_array<float>();
    r.polar = in.get_array<Polar>();
    const auto flat = in.get_array<double>();
    if (flat.size() % 3 != 0) throw Error("keypoints stage payload: a point without 3 coordinates");
    for (std::size_t i = 0; i < flat.size(); i += 3)
        r.points.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
    const std::size_t n = r.features.keypoints.size();
    const auto side = static_cast<std::size_t>(2 * std::max(0, r.patch_radius) + 1);
    if (r.features.descriptors.count() != n || r.positions.size() != n || r.polar.size() != n ||
        r.points.size() != n || r.anchor_rows.size() != n || r.anchor_columns.size() != n ||
        r.patch_radius < 0 || r.patches.size() != (r.patch_radius > 0 ? n * side * side : 0)) {
        throw Error(
            "keypoints stage payload: keypoints, descriptors and positions differ in number");
    }
    r.scanner = get_vector(in);
    r.angular_step = in.get<double>();
    r.detected = in.get<std::uint64_t>();
    r.seconds = in.get<double>();
    const auto zones = in.get<std::uint64_t>();
    if (zones > payload.size()) throw Error("keypoints stage payload: too many zones");
    for (std::uint64_t z = 0; z < zones; ++z) {
        r.zone_names.push_back(get_text(in));
        WallFrame f;
        f.centroid = get_vector(in);
        f.normal = get_vector(in);
        f.horizontal = get_vector(in);
        f.vertical = get_vector(in);
        f.rms = in.get<double>();
        f.points = in.get<std::uint64_t>();
        f.horizontal_surface = in.get<std::uint8_t>() != 0;
        f.undefined_reason = get_text(in);
        r.walls.push_back(std::move(f));
    }
    in.finish();
    return r;
}

KeypointEpoch measure_keypoints(const KeypointConfig& config, const KeypointReference& reference,
                                const std::vector<Scan>& scans, const StageOutputs& outputs) {
    const Scan& scan = structured_scan(scans, "epoch");
    Described d = describe_scan(config, scan);
    KeypointEpoch out;
    out.detected = d.detected;
    out.described = d.features.keypoints.size();
    out.images_s = d.images_s;
    out.detection_s = d.detection_s;
    out.description_s = d.description_s;

    auto t0 = Clock::now();
    MatchingParameters mp;
    mp.window_radius = config.window_deg * kDeg;
    mp.ratio = config.ratio;
    mp.mutual = config.mutual;
    const auto pairs = match_keypoints(reference.positions, reference.features.descriptors,
                                       d.positions, d.features.descriptors, mp);
    out.pairs = pairs.size();
    out.matching_s = since(t0);

    t0 = Clock::now();
    // The epoch's point in the reference frame: its file's pose, then the range scale and
    // the registration (the map M3C2 uses, m3c2_stage.hpp).
    const EpochToReference map = epoch_to_reference(outputs, reference.scanner);
    const int radius = reference.patch_radius;
    const std::size_t patch_size = static_cast<std::size_t>((2 * radius + 1) * (2 * radius + 1));
    IntensityPatch patch;
    patch.radius = radius;
    for (const auto& pair : pairs) {
        const Keypoint& a = reference.features.keypoints[pair.reference];
        const Keypoint& b = d.features.keypoints[pair.epoch];
        // The anchor's place in the epoch's image, first from the keypoints' offset.
        double row = b.row + (reference.anchor_rows[pair.reference] - a.row);
        double column = b.column + (reference.anchor_columns[pair.reference] - a.column);
        if (radius > 0) {
            patch.row = static_cast<int>(reference.anchor_rows[pair.reference]);
            patch.column = static_cast<int>(reference.anchor_columns[pair.reference]);
            const auto first = reference.patches.begin() +
                               static_cast<std::ptrdiff_t>(pair.reference * patch_size);
            patch.values.assign(first, first + static_cast<std::ptrdiff_t>(patch_size));
            const auto found = match_patch(patch, d.images, row, column);
            if (!found) {
                ++out.dropped_patch;
                continue;
            }
            row = found->row;
            column = found->column;
        }
        const PolarAt pb = polar_at(d.images, row, column);
        if (out.count(pb.dropped)) continue;
        const Polar& pa = reference.polar[pair.reference];
        KeypointMatch m;
        m.reference_row = reference.anchor_rows[pair.reference];
        m.reference_column = reference.anchor_columns[pair.reference];
        m.row = row;
        m.column = column;
        set_polar(m, pa, pb.polar);
        m.reference_point = reference.points[pair.reference];
        m.point = map.apply(d.images.pose * cartesian_of(pb.polar));
        m.descriptor_distance = pair.distance;
        out.matches.push_back(m);
    }
    out.to_3d_s = since(t0);
    return out;
}

KeypointSegmentsResult keypoint_segments(const KeypointConfig& config,
                                         const KeypointReference& reference,
                                         std::vector<KeypointMatch> matches,
                                         const StageOutputs& outputs) {
    const auto t0 = Clock::now();
    KeypointSegmentsResult out;
    OutlierParameters op;
    op.k = config.mad_k;
    SegmentParameters sp;
    sp.min_matches = static_cast<std::size_t>(config.min_matches);
    sp.orientation = m3c2::Orientation::towards(reference.scanner);
    // The registration's σ at the segment's centroid: its wall's, else its matches' mean
    // reference point; without a registration, `registration_error`.
    const auto sigma_at = [&](const SegmentDisplacement& d, std::span<const KeypointMatch> in) {
        if (!outputs.to_reference) return config.registration_error;
        Eigen::Vector3d c = d.wall.centroid;
        if (!c.allFinite()) {
            c.setZero();
            std::size_t n = 0;
            for (const auto& m : in) {
                if (m.segment != d.segment) continue;
                c += m.reference_point;
                ++n;
            }
            if (n == 0) return 0.0;
            c /= double(n);
        }
        return registration_sigma_at(*outputs.to_reference, c);
    };
    // The sampling (config.max_sample_spacing): the median of range × step over the
    // segment's matches; a coarser one makes the segment undefined, whatever its vectors say.
    const auto check_sampling = [&](SegmentDisplacement& d, std::span<const KeypointMatch> in,
                                    int segment) {
        std::vector<double> spacing;
        for (const auto& m : in)
            if (m.segment == segment) spacing.push_back(m.reference_range * reference.angular_step);
        if (spacing.empty() || !d.defined()) return;
        std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
        const double median = spacing[spacing.size() / 2];
        if (median <= config.max_sample_spacing) return;
        SegmentDisplacement undefined;  // figures NaN; the counts and the wall stay
        undefined.segment = d.segment;
        undefined.matches = d.matches;
        undefined.count = d.count;
        undefined.wall = d.wall;
        d = std::move(undefined);
        d.undefined_reason = fmt::format(
            "undersampled: the scan samples this surface every {:.1f} mm (range × step), "
            "coarser than keypoints.max_sample_spacing = {:.1f} mm; its intensity image is "
            "aliased",
            1e3 * median, 1e3 * config.max_sample_spacing);
    };
    if (config.segments == KeypointSegments::zones) {
        for (std::size_t z = 0; z < reference.zone_names.size() && z < config.zones.size(); ++z) {
            // The incidence cut (config.max_incidence_deg): |cos| of the angle between the
            // beam and the wall's normal.
            const WallFrame& wall = reference.walls[z];
            const double min_cos = std::cos(config.max_incidence_deg * kDeg);
            const auto grazing = [&](const KeypointMatch& m) {
                if (!wall.defined() || config.max_incidence_deg >= 90.0) return false;
                const Eigen::Vector3d beam = (m.reference_point - reference.scanner).normalized();
                return std::abs(beam.dot(wall.normal)) < min_cos;
            };
            std::vector<KeypointMatch> in;
            for (const auto& m : matches) {
                if (config.zones[z].contains(m.reference_point) && !grazing(m)) {
                    in.push_back(m);
                    in.back().segment = 0;
                }
            }
            const OutlierResult filtered = filter_outliers(in, op);
            KeypointSegmentResult r;
            r.zone = reference.zone_names[z];
            r.displacement = segment_displacement(in, filtered.removed_by, 0, sp,
                                                  reference.walls[z].defined()
                                                      ? std::optional<WallFrame>(reference.walls[z])
                                                      : std::nullopt);
            check_sampling(r.displacement, in, 0);
            r.registration_sigma = sigma_at(r.displacement, in);
            out.segments.push_back(std::move(r));
        }
    } else {
        const double width = config.band_width_deg * kDeg;
        std::map<int, int> present;
        for (auto& m : matches) {
            m.segment = vertical_angle_band(m.reference_elevation, width);
            ++present[m.segment];
        }
        const OutlierResult filtered = filter_outliers(matches, op);
        for (const auto& [band, count] : present) {
            KeypointSegmentResult r;
            r.zone = keypoint_band_zone(band, width);
            r.band_definition = keypoint_band_zone_definition(band, width);
            r.displacement = segment_displacement(matches, filtered.removed_by, band, sp);
            check_sampling(r.displacement, matches, band);
            r.registration_sigma = sigma_at(r.displacement, matches);
            out.segments.push_back(std::move(r));
        }
    }
    out.filtering_s = since(t0);
    return out;
}

std::vector<std::string> keypoint_segment_zones(const KeypointConfig& config) {
    std::vector<std::string> zones;
    if (config.segments == KeypointSegments::zones) {
        for (const auto& z : config.zones) zones.push_back(z.name);
        return zones;
    }
    const double width = config.band_width_deg * kDeg;
    for (int band = 0; band <= vertical_angle_band(std::numbers::pi / 2, width); ++band)
        zones.push_back(keypoint_band_zone(band, width));
    return zones;
}

StageVerdict run_keypoints(const KeypointConfig& config, const EpochInput& input,
                           ReferenceEpoch& reference, ReferenceCache& cache,
                           const StageOutputs& outputs, const SeriesReader& series,
                           std::vector<std::pair<std::string, std::string>>& new_zones,
                           EpochResults& results) {
    // An unstructured scan has no spherical images of its own: the method does not apply,
    // and the epoch's other results stand.
    if (std::none_of(input.scans->begin(), input.scans->end(),
                     [](const Scan& s) { return s.grid.has_value(); })) {
        StageVerdict skipped;
        skipped.note = "not run: no structured scan in the epoch";
        return skipped;
    }
    const auto product = cache.get<KeypointReference>(
        reference,
        ProductKey{KeypointReference::kStage, keypoint_reference_parameters(config),
                   KeypointReference::kFormatVersion},
        [&](const std::vector<Scan>& scans) { return prepare_keypoint_reference(config, scans); });
    KeypointEpoch epoch = measure_keypoints(config, *product, *input.scans, outputs);
    const std::size_t in_3d = epoch.matches.size();
    const KeypointSegmentsResult segments =
        keypoint_segments(config, *product, std::move(epoch.matches), outputs);

    // Zone rows, and this epoch's observations of the model.
    const double t_now =
        static_cast<double>(input.epoch.acquired - reference.epoch().acquired) / 3600.0;
    std::size_t defined = 0, kept = 0;
    std::string first_undefined;  // the first undefined segment and why, for the note
    std::vector<ZoneResult> rows;
    for (const auto& s : segments.segments) {
        if (!s.band_definition.empty()) new_zones.emplace_back(s.zone, s.band_definition);
        auto r = keypoint_zone_results(s.zone, s.displacement, s.registration_sigma);
        rows.insert(rows.end(), r.begin(), r.end());
        defined += s.displacement.defined();
        kept += s.displacement.count;
        if (!s.displacement.defined() && first_undefined.empty())
            first_undefined = s.zone + ": " + s.displacement.undefined_reason;
    }
    // The model d(t, z) over the stored epochs and this one (step 7), per quantity.
    const auto zones = keypoint_segment_zones(config);
    for (const auto& quantity : config.model_quantities) {
        auto inputs = stored_model_inputs(series, zones, quantity, reference.epoch().acquired);
        std::map<std::string, double> height;
        for (const auto& row : rows)
            if (row.quantity == kKeypointHeight) height[row.zone] = row.value;
        for (const auto& row : rows) {
            if (row.quantity != quantity) continue;
            const auto z = height.find(row.zone);
            if (z == height.end()) continue;
            inputs.push_back({row.zone, input.epoch.id, {t_now, z->second, row.value}});
        }
        std::vector<ModelObservation> observations;
        observations.reserve(inputs.size());
        for (const auto& in : inputs) observations.push_back(in.observation);
        const DisplacementModel model = fit_displacement_model(observations);
        results.keypoint_models.push_back(
            keypoint_model_row(quantity, "time_h", model, inputs, input.epoch.id));
    }
    results.zone_results.insert(results.zone_results.end(), std::make_move_iterator(rows.begin()),
                                std::make_move_iterator(rows.end()));

    StageVerdict verdict;
    verdict.note = fmt::format(
        "reference {} keypoints; {} + {}: {} of {} keypoints described, {} matched, {} in 3-D, {} "
        "kept; {} of {} "
        "segments defined; s: images {:.2f}, detection {:.2f}, description {:.2f}, matching "
        "{:.2f}, 3-D {:.2f}, filtering {:.2f}",
        product->features.keypoints.size(), config.detector, config.descriptor, epoch.described,
        epoch.detected, epoch.pairs, in_3d, kept, defined, segments.segments.size(), epoch.images_s,
        epoch.detection_s, epoch.description_s, epoch.matching_s, epoch.to_3d_s,
        segments.filtering_s);
    if (!first_undefined.empty()) verdict.note += "; undefined e.g. " + first_undefined;
    return verdict;
}

}  // namespace tlsmon
