#include "pipeline/keypoint_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <span>

#include "algorithms/keypoints/keypoint_to_3d.hpp"
#include "algorithms/keypoints/opencv_features.hpp"
#include "algorithms/keypoints/patch_refinement.hpp"
#include "algorithms/keypoints/zone_strata.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "core/angles.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"
#include "pipeline/keypoint_results.hpp"
#include "pipeline/m3c2_stage.hpp"

namespace tlsmon {

namespace {

using namespace keypoints;
using Clock = std::chrono::steady_clock;

// Pixels kept between a keypoint and an empty pixel (spherical_image.hpp, detection_mask).
constexpr int kMaskMargin = 2;
// Zone boxes grown by this before they confine detection: an epoch's scan lies in its file's
// frame, a few centimetres from the reference's before registration.
constexpr double kBoxMargin = 0.25;  // m

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The structured scans of an epoch, in file order.
std::vector<const Scan*> structured_scans(const std::vector<Scan>& scans, const char* which) {
    std::vector<const Scan*> out;
    for (const auto& s : scans)
        if (s.grid) out.push_back(&s);
    if (out.empty()) {
        throw Error(std::string("keypoints: the ") + which +
                    " holds no structured scan (a grid of rows and columns, as PTX or a gridded "
                    "E57 has): the method needs the scanner's spherical images");
    }
    return out;
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
    const FeatureParameters fp = features_of(c);
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

// The registration's covariance at a project-frame point: Σ_p = J·Σ·Jᵀ at its place in the
// epoch's frame (registration_error.hpp; Niemeier 2008, §2.4).
Eigen::Matrix3d covariance_at_project_point(const registration::RigidTransform& T,
                                            const Eigen::Vector3d& q) {
    const Eigen::Vector3d x = T.rotation.transpose() * (q - T.translation) / T.scale;
    return registration::registration_covariance_at(T, x);
}

// Scan `k` of the epoch against the reference's scan `k`: images, keypoints, matching in the
// angular window, refinement, 3-D; its matches and times added to `out`.
void measure_scan(const KeypointConfig& config, const KeypointReference& reference, int k,
                  const Scan& scan, const EpochToReference& map, KeypointEpoch& out) {
    const KeypointScanReference& ref = reference.scans[static_cast<std::size_t>(k)];
    Described d = describe_scan(config, scan);
    out.detected += d.detected;
    out.described += d.features.keypoints.size();
    out.images_s += d.images_s;
    out.detection_s += d.detection_s;
    out.description_s += d.description_s;

    auto t0 = Clock::now();
    MatchingParameters mp;
    mp.window_radius = config.window_deg * kDeg;
    mp.window_m = config.window_m;
    mp.ratio = config.ratio;
    mp.mutual = config.mutual;
    std::vector<double> ranges;
    ranges.reserve(ref.polar.size());
    for (const Polar& p : ref.polar) ranges.push_back(p.range);
    const auto pairs = match_keypoints(ref.positions, ref.features.descriptors, d.positions,
                                       d.features.descriptors, mp, ranges);
    out.pairs += pairs.size();
    out.matching_s += since(t0);

    t0 = Clock::now();
    const int radius = reference.patch_radius;
    const std::size_t patch_size = static_cast<std::size_t>((2 * radius + 1) * (2 * radius + 1));
    IntensityPatch patch;
    patch.radius = radius;
    // The refinement's image (its prefilter; the reference's patches were cut from the same).
    const BSplineImage smooth = bspline_image(
        radius > 0 ? gaussian_prefiltered(d.images, reference.prefilter_px) : Image{});
    for (const auto& pair : pairs) {
        const Keypoint& a = ref.features.keypoints[pair.reference];
        const Keypoint& b = d.features.keypoints[pair.epoch];
        // The anchor's place in the epoch's image, first from the keypoints' offset.
        double row = b.row + (ref.anchor_rows[pair.reference] - a.row);
        double column = b.column + (ref.anchor_columns[pair.reference] - a.column);
        if (radius > 0) {
            patch.row = static_cast<int>(ref.anchor_rows[pair.reference]);
            patch.column = static_cast<int>(ref.anchor_columns[pair.reference]);
            const auto first =
                ref.patches.begin() + static_cast<std::ptrdiff_t>(pair.reference * patch_size);
            patch.values.assign(first, first + static_cast<std::ptrdiff_t>(patch_size));
            const auto found = match_patch(patch, smooth, row, column);
            if (!found) {
                ++out.dropped_patch;
                continue;
            }
            row = found->row;
            column = found->column;
        }
        const PolarAt pb = polar_at(d.images, row, column);
        if (out.count(pb.dropped)) continue;
        KeypointMatch m;
        m.reference_row = ref.anchor_rows[pair.reference];
        m.reference_column = ref.anchor_columns[pair.reference];
        m.row = row;
        m.column = column;
        set_polar(m, ref.polar[pair.reference], pb.polar);
        m.reference_point = ref.points[pair.reference];
        m.point = map.apply(d.images.pose * cartesian_of(pb.polar));
        m.descriptor_distance = pair.distance;
        m.scan = k;
        out.matches.push_back(m);
    }
    out.to_3d_s += since(t0);
}

// The sample spacing of a match: its reference range × its scan's angular step.
double sample_spacing(const KeypointReference& reference, const KeypointMatch& m) {
    return m.reference_range * reference.scans[static_cast<std::size_t>(m.scan)].angular_step;
}

// Of one segment's matches, those of the scan that samples it finest (the smallest median
// range × step): a detail scan over part of a zone measures it, not the overview's coarser
// pixels there, and two scans' vectors are never mixed in one mean.
std::vector<KeypointMatch> finest_scan_matches(std::vector<KeypointMatch> in,
                                               const KeypointReference& reference) {
    std::map<int, std::vector<double>> spacing;
    for (const auto& m : in) spacing[m.scan].push_back(sample_spacing(reference, m));
    if (spacing.size() < 2) return in;
    int finest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [scan, values] : spacing) {
        const double median = median_high(values);
        if (median < best) {
            best = median;
            finest = scan;
        }
    }
    std::erase_if(in, [&](const KeypointMatch& m) { return m.scan != finest; });
    return in;
}

}  // namespace

std::string keypoint_reference_parameters(const KeypointConfig& c) {
    std::string s = fmt::format("detector={};descriptor={};clahe={};segments={};patch={}",
                                c.detector, c.descriptor, c.clahe ? 1 : 0,
                                c.segments == KeypointSegments::zones ? "zones" : "bands",
                                c.refine ? c.patch_radius : 0);
    if (c.refine) s += fmt::format(";prefilter={:.17g}", c.prefilter_px);
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

// One structured scan's part of the reference product.
KeypointScanReference scan_reference(const KeypointConfig& config, const Scan& scan) {
    Described d = describe_scan(config, scan);
    KeypointScanReference out;
    out.detected = d.detected;
    out.angular_step = std::max(d.images.azimuth_step, d.images.elevation_step);
    // Only keypoints the range image can take to 3-D: the others can never give a vector.
    const Image smooth =
        config.refine ? gaussian_prefiltered(d.images, config.prefilter_px) : Image{};
    const auto& kp = d.features.keypoints;
    const auto& desc = d.features.descriptors;
    out.features.descriptors.binary = desc.binary;
    out.features.descriptors.length = desc.length;
    for (std::size_t i = 0; i < kp.size(); ++i) {
        double row = kp[i].row, column = kp[i].column;
        PolarAt at;
        if (config.refine) {
            const int r = static_cast<int>(std::lround(row)),
                      c = static_cast<int>(std::lround(column));
            const auto patch = intensity_patch(smooth, r, c, config.patch_radius);
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
    return out;
}

KeypointReference prepare_keypoint_reference(const KeypointConfig& config,
                                             const std::vector<Scan>& scans) {
    const auto t0 = Clock::now();
    const auto structured = structured_scans(scans, "reference epoch");
    KeypointReference out;
    out.scanner = structured.front()->scanner_position();
    out.patch_radius = config.refine ? config.patch_radius : 0;
    out.prefilter_px = config.refine ? config.prefilter_px : 0.0;
    for (const Scan* scan : structured) out.scans.push_back(scan_reference(config, *scan));
    if (config.segments == KeypointSegments::zones) {
        // Each zone's wall: a plane fitted to the reference's points in it, of every scan
        // (issue 12: "from a plane fit to the reference points, not a constant").
        const auto towards = m3c2::Orientation::towards(out.scanner);
        for (const auto& z : config.zones) {
            std::vector<Eigen::Vector3d> inside;
            for (const auto& scan : scans)
                for (const auto& p : scan.xyz)
                    if (p.allFinite() && z.contains(p)) inside.push_back(p);
            out.zone_names.push_back(z.name);
            out.walls.push_back(fit_wall_frame(inside, towards));
            out.wall_cells.push_back(
                vertical_angles(wall_cell_centres(inside, out.walls.back()), out.scanner));
        }
    }
    out.seconds = since(t0);
    return out;
}

KeypointEpoch measure_keypoints(const KeypointConfig& config, const KeypointReference& reference,
                                const std::vector<Scan>& scans, const StageOutputs& outputs) {
    const auto structured = structured_scans(scans, "epoch");
    KeypointEpoch out;
    out.scans = std::min(structured.size(), reference.scans.size());
    // The epoch's point in the reference frame: its file's pose, then the range scale and
    // the registration (the map M3C2 uses, m3c2_stage.hpp).
    const EpochToReference map = epoch_to_reference(outputs, reference.scanner);
    for (std::size_t k = 0; k < out.scans; ++k)
        measure_scan(config, reference, static_cast<int>(k), *structured[k], map, out);
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
    op.noise = config.noise;
    if (config.refine) op.averaged_pixels = std::pow(2.0 * config.patch_radius + 1.0, 2);
    for (const auto& scan : reference.scans) op.angular_steps.push_back(scan.angular_step);
    SegmentParameters sp;
    sp.min_matches = static_cast<std::size_t>(config.min_matches);
    // One refinement patch: matches anchored within it share pixels and err together (several
    // keypoints of one feature, at the detector's scales, share an anchor).
    sp.cluster_px = 2.0 * config.patch_radius + 1.0;
    sp.orientation = m3c2::Orientation::towards(reference.scanner);
    // The registration's covariance at the segment's centroid: its wall's, else its matches'
    // mean reference point; without a registration, `registration_error` in every direction.
    const auto covariance_at = [&](const SegmentDisplacement& d,
                                   std::span<const KeypointMatch> in) -> Eigen::Matrix3d {
        if (!outputs.to_reference)
            return config.registration_error * config.registration_error *
                   Eigen::Matrix3d::Identity();
        Eigen::Vector3d c = d.wall.centroid;
        if (!c.allFinite()) {
            c.setZero();
            std::size_t n = 0;
            for (const auto& m : in) {
                if (m.segment != d.segment) continue;
                c += m.reference_point;
                ++n;
            }
            if (n == 0) return Eigen::Matrix3d::Zero();
            c /= double(n);
        }
        return covariance_at_project_point(*outputs.to_reference, c);
    };
    // The sampling (config.max_sample_spacing): the median of range × step over the
    // segment's matches; a coarser one makes the segment undefined, whatever its vectors say.
    const auto check_sampling = [&](SegmentDisplacement& d, std::span<const KeypointMatch> in,
                                    int segment) {
        std::vector<double> spacing;
        for (const auto& m : in)
            if (m.segment == segment) spacing.push_back(sample_spacing(reference, m));
        if (spacing.empty() || !d.defined()) return;
        const double median = median_high(std::move(spacing));
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
            in = finest_scan_matches(std::move(in), reference);
            // The filters judge each match against its band of the vertical angle, the case
            // study's segment, not against the whole zone: over a face that bends, the
            // displacement grows with the height, and against the zone's median the upper
            // part's matches were removed as outliers (docs/keypoints.md, "Zones that bend").
            const double width = config.band_width_deg * kDeg;
            for (auto& m : in) m.segment = vertical_angle_band(m.reference_elevation, width);
            const OutlierResult filtered = filter_outliers(in, op);
            KeypointSegmentResult r;
            r.zone = reference.zone_names[z];
            r.displacement =
                stratified_displacement(in, filtered.removed_by, wall, reference.wall_cells[z],
                                        {.segment = sp,
                                         .min_stratum_matches = sp.min_matches,
                                         .band_width = width,
                                         .scanner = reference.scanner});
            for (auto& m : in) m.segment = 0;
            check_sampling(r.displacement, in, 0);
            r.registration_covariance = covariance_at(r.displacement, in);
            r.removed_by = filtered.removed_by;
            r.matches = std::move(in);
            out.segments.push_back(std::move(r));
        }
    } else {
        const double width = config.band_width_deg * kDeg;
        std::map<int, std::vector<KeypointMatch>> bands;
        for (auto& m : matches) {
            m.segment = vertical_angle_band(m.reference_elevation, width);
            bands[m.segment].push_back(m);
        }
        matches.clear();
        for (auto& [band, in] : bands) {
            const auto finest = finest_scan_matches(std::move(in), reference);
            matches.insert(matches.end(), finest.begin(), finest.end());
        }
        const OutlierResult filtered = filter_outliers(matches, op);
        for (const auto& entry : bands) {
            const int band = entry.first;
            KeypointSegmentResult r;
            r.zone = keypoint_band_zone(band, width);
            r.band_definition = keypoint_band_zone_definition(band, width);
            r.displacement = segment_displacement(matches, filtered.removed_by, band, sp);
            check_sampling(r.displacement, matches, band);
            r.registration_covariance = covariance_at(r.displacement, matches);
            for (std::size_t i = 0; i < matches.size(); ++i) {
                if (matches[i].segment != band) continue;
                r.matches.push_back(matches[i]);
                r.removed_by.push_back(filtered.removed_by[i]);
            }
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

std::string KeypointStage::reference_parameters() const {
    return keypoint_reference_parameters(config_);
}

KeypointReference KeypointStage::prepare_reference(const std::vector<Scan>& reference_scans) const {
    return prepare_keypoint_reference(config_, reference_scans);
}

// An unstructured scan has no spherical images of its own: the method does not apply, and
// the epoch's other results stand.
std::string KeypointStage::not_measured(const StageContext& ctx) const {
    const auto& scans = *ctx.input.scans;
    if (std::any_of(scans.begin(), scans.end(), [](const Scan& s) { return s.grid.has_value(); }))
        return {};
    return "not run: no structured scan in the epoch";
}

StageVerdict KeypointStage::measure(StageContext& ctx, const KeypointReference& reference) const {
    const KeypointConfig& config = config_;
    const EpochInput& input = ctx.input;
    const StageOutputs& outputs = ctx.outputs;
    EpochResults& results = ctx.results;
    KeypointEpoch epoch = measure_keypoints(config, reference, *input.scans, outputs);
    const std::size_t in_3d = epoch.matches.size();
    const KeypointSegmentsResult segments =
        keypoint_segments(config, reference, std::move(epoch.matches), outputs);

    // Zone rows, and this epoch's observations of the model.
    const double t_now =
        static_cast<double>(input.epoch.acquired - ctx.reference.epoch().acquired) / 3600.0;
    std::size_t defined = 0, kept = 0;
    std::string first_undefined;  // the first undefined segment and why, for the note
    std::vector<ZoneResult> rows;
    for (const auto& s : segments.segments) {
        if (!s.band_definition.empty()) results.new_zones.push_back({s.zone, s.band_definition});
        auto r = keypoint_zone_results(s.zone, s.displacement, s.registration_covariance);
        rows.insert(rows.end(), r.begin(), r.end());
        defined += s.displacement.defined();
        kept += s.displacement.count;
        if (!s.displacement.defined() && first_undefined.empty())
            first_undefined = s.zone + ": " + s.displacement.undefined_reason;
    }
    // The model d(t, z) over the stored epochs and this one (step 7), per quantity.
    const auto zones = keypoint_segment_zones(config);
    for (const auto& quantity : config.model_quantities) {
        std::vector<KeypointModelInput> inputs;
        if (ctx.history.series) {
            inputs = stored_model_inputs(*ctx.history.series, zones, quantity,
                                         ctx.reference.epoch().acquired);
        }
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
        "reference {} keypoints in {} scan(s); {} + {}: {} of {} keypoints described, {} matched, "
        "{} in 3-D, {} "
        "kept; {} of {} "
        "segments defined; s: images {:.2f}, detection {:.2f}, description {:.2f}, matching "
        "{:.2f}, 3-D {:.2f}, filtering {:.2f}",
        reference.keypoints(), reference.scans.size(), config.detector, config.descriptor,
        epoch.described, epoch.detected, epoch.pairs, in_3d, kept, defined,
        segments.segments.size(), epoch.images_s, epoch.detection_s, epoch.description_s,
        epoch.matching_s, epoch.to_3d_s, segments.filtering_s);
    if (!first_undefined.empty()) verdict.note += "; undefined e.g. " + first_undefined;
    return verdict;
}

}  // namespace tlsmon
