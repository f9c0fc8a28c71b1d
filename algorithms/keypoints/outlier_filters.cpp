#include "algorithms/keypoints/outlier_filters.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::keypoints {
namespace {

// √(π/2): the mean absolute deviation · 1.2533 estimates σ of a normal distribution.
constexpr double kMeanDeviationToSigma = 1.2533;

void check_finite(std::size_t i, const KeypointMatch& m) {
    const auto require = [&](double value, const char* field) {
        if (!std::isfinite(value))
            throw Error("keypoint match " + std::to_string(i) + ": " + field + " is not finite");
    };
    require(m.reference_row, "reference_row");
    require(m.reference_column, "reference_column");
    require(m.row, "row");
    require(m.column, "column");
    require(m.reference_range, "reference_range");
    require(m.range, "range");
    require(m.reference_azimuth, "reference_azimuth");
    require(m.azimuth, "azimuth");
    require(m.reference_elevation, "reference_elevation");
    require(m.elevation, "elevation");
    if (!m.reference_point.allFinite())
        throw Error("keypoint match " + std::to_string(i) + ": reference_point is not finite");
    if (!m.point.allFinite())
        throw Error("keypoint match " + std::to_string(i) + ": point is not finite");
}

void validate(const OutlierParameters& p) {
    if (!(p.k > 0) || !std::isfinite(p.k))
        throw Error("outlier filters: k must be a positive number, got " + std::to_string(p.k));
    if (!(p.columns_per_turn >= 0) || !std::isfinite(p.columns_per_turn))
        throw Error("outlier filters: columns_per_turn must be >= 0, got " +
                    std::to_string(p.columns_per_turn));
    if (p.min_matches < 1) throw Error("outlier filters: min_matches must be >= 1");
    if (p.noise && !(p.noise->range_sigma_a >= 0 && p.noise->range_sigma_b_ppm >= 0 &&
                     p.noise->angular_sigma_arcsec >= 0 && std::isfinite(p.noise->range_sigma_a) &&
                     std::isfinite(p.noise->range_sigma_b_ppm) &&
                     std::isfinite(p.noise->angular_sigma_arcsec)))
        throw Error("outlier filters: the scanner's noise must be finite and >= 0");
    if (!(p.averaged_pixels >= 1) || !std::isfinite(p.averaged_pixels))
        throw Error("outlier filters: averaged_pixels must be >= 1");
}

// The scalar a filter tests, for the filters other than angle_to_median.
double quantity(OutlierFilter filter, const KeypointMatch& m, const OutlierParameters& p) {
    switch (filter) {
        case OutlierFilter::row_difference:
            return m.row - m.reference_row;
        case OutlierFilter::column_difference:
            return periodic_difference(m.column, m.reference_column, p.columns_per_turn);
        case OutlierFilter::range_difference:
            return m.range - m.reference_range;
        case OutlierFilter::horizontal_angle_difference:
            return periodic_difference(m.azimuth, m.reference_azimuth, 2 * std::numbers::pi);
        case OutlierFilter::vertical_angle_difference:
            return m.elevation - m.reference_elevation;
        case OutlierFilter::dx:
            return m.displacement().x();
        case OutlierFilter::dy:
            return m.displacement().y();
        case OutlierFilter::dz:
            return m.displacement().z();
        case OutlierFilter::magnitude:
            return m.displacement().norm();
        default:
            return std::numeric_limits<double>::quiet_NaN();
    }
}

// The noise of one match's value of `filter`: the scanner's σ of one measurement at the
// match's reference range (header); NaN where there is none.
double single_noise(OutlierFilter filter, const KeypointMatch& m, const OutlierParameters& p,
                    double median_length) {
    const ScannerNoise& n = *p.noise;
    const double r = m.reference_range;
    const auto step = [&]() {
        const auto k = static_cast<std::size_t>(m.scan);
        return m.scan >= 0 && k < p.angular_steps.size() && p.angular_steps[k] > 0
                   ? p.angular_steps[k]
                   : std::numeric_limits<double>::quiet_NaN();
    };
    switch (filter) {
        case OutlierFilter::row_difference:
        case OutlierFilter::column_difference:
            return n.angular_sigma() / step();
        case OutlierFilter::range_difference:
            return n.range_sigma(r);
        case OutlierFilter::horizontal_angle_difference:
        case OutlierFilter::vertical_angle_difference:
            return n.angular_sigma();
        case OutlierFilter::angle_to_median:
            return median_length > 0 ? std::min(std::numbers::pi, n.point_sigma(r) / median_length)
                                     : std::numeric_limits<double>::quiet_NaN();
        default:
            return n.point_sigma(r);
    }
}

// The floor of σ over the judged matches: √2 · the median of their single measurements'
// noise (a difference of two) / √averaged_pixels; 0 without a noise model or a defined noise.
double noise_floor(OutlierFilter filter, std::span<const KeypointMatch> matches,
                   const std::vector<std::size_t>& kept, const std::vector<double>& value,
                   const OutlierParameters& p, double median_length) {
    if (!p.noise) return 0.0;
    std::vector<double> noise;
    for (std::size_t j = 0; j < kept.size(); ++j) {
        if (std::isnan(value[j])) continue;
        const double s = single_noise(filter, matches[kept[j]], p, median_length);
        if (std::isfinite(s)) noise.push_back(s);
    }
    return noise.empty()
               ? 0.0
               : std::numbers::sqrt2 * median(std::move(noise)) / std::sqrt(p.averaged_pixels);
}

// Whether a value's deviation from the median is beyond the threshold. The angle to the
// median vector is judged on one side only: an angle below the median is better agreement
// with the segment's direction, never a reason to remove a match (two-sided, the filter
// would discard the vectors most parallel to the median whenever the angles' median lies
// more than the threshold above 0).
bool outside(OutlierFilter filter, double deviation, double threshold) {
    if (filter == OutlierFilter::angle_to_median) return deviation > threshold;
    return std::abs(deviation) > threshold;
}

// Runs one filter over `kept` (indices into matches), erasing and marking what it removes.
FilterStep run_filter(OutlierFilter filter, std::span<const KeypointMatch> matches,
                      std::vector<std::size_t>& kept, std::vector<OutlierFilter>& removed_by,
                      const OutlierParameters& p) {
    FilterStep step;
    step.filter = filter;
    step.tested = kept.size();
    if (kept.size() < p.min_matches) {
        step.skipped = true;
        return step;
    }
    // The values tested; NaN marks a match this filter cannot judge (a zero vector's angle).
    std::vector<double> value(kept.size());
    double median_length = 0;  // |median vector|, for the angle's noise floor
    if (filter == OutlierFilter::angle_to_median) {
        std::vector<double> c(kept.size());
        Eigen::Vector3d median_vector;
        for (int axis = 0; axis < 3; ++axis) {
            for (std::size_t j = 0; j < kept.size(); ++j)
                c[j] = matches[kept[j]].displacement()[axis];
            median_vector[axis] = median(c);
        }
        if (median_vector.isZero(0.0)) {
            step.skipped = true;
            return step;
        }
        median_length = median_vector.norm();
        for (std::size_t j = 0; j < kept.size(); ++j) {
            const Eigen::Vector3d d = matches[kept[j]].displacement();
            // atan2(|d × m|, d · m): accurate also for nearly parallel vectors.
            value[j] = d.isZero(0.0)
                           ? std::numeric_limits<double>::quiet_NaN()
                           : std::atan2(d.cross(median_vector).norm(), d.dot(median_vector));
        }
    } else {
        for (std::size_t j = 0; j < kept.size(); ++j)
            value[j] = quantity(filter, matches[kept[j]], p);
    }
    std::vector<double> judged;
    judged.reserve(value.size());
    for (double v : value)
        if (!std::isnan(v)) judged.push_back(v);
    if (judged.size() < p.min_matches) {
        step.skipped = true;
        return step;
    }
    const MedianAndMad m = median_and_mad(judged);
    step.median = m.median;
    step.mad = m.mad;
    step.sigma = kMadToSigma * m.mad;
    if (!(m.mad > 0)) {
        // More than half the values equal the median: fall back to the mean absolute
        // deviation, which is zero only when all of them do.
        step.mad_was_zero = true;
        double sum = 0;
        for (double v : judged) sum += std::abs(v - m.median);
        step.sigma = kMeanDeviationToSigma * sum / static_cast<double>(judged.size());
    }
    step.floor = noise_floor(filter, matches, kept, value, p, median_length);
    if (step.sigma < step.floor) {
        step.sigma = step.floor;
        step.floored = true;
    }
    if (!(step.sigma > 0)) {
        step.skipped = true;
        return step;
    }
    step.threshold = p.k * step.sigma;
    std::vector<std::size_t> still;
    still.reserve(kept.size());
    for (std::size_t j = 0; j < kept.size(); ++j) {
        if (!std::isnan(value[j]) && outside(filter, value[j] - m.median, step.threshold)) {
            removed_by[kept[j]] = filter;
            ++step.removed;
        } else {
            still.push_back(kept[j]);
        }
    }
    kept.swap(still);
    return step;
}

}  // namespace

std::string_view outlier_filter_name(OutlierFilter filter) {
    switch (filter) {
        case OutlierFilter::none:
            return "";
        case OutlierFilter::row_difference:
            return "row_difference";
        case OutlierFilter::column_difference:
            return "column_difference";
        case OutlierFilter::range_difference:
            return "range_difference";
        case OutlierFilter::horizontal_angle_difference:
            return "horizontal_angle_difference";
        case OutlierFilter::vertical_angle_difference:
            return "vertical_angle_difference";
        case OutlierFilter::dx:
            return "dx";
        case OutlierFilter::dy:
            return "dy";
        case OutlierFilter::dz:
            return "dz";
        case OutlierFilter::magnitude:
            return "magnitude";
        case OutlierFilter::angle_to_median:
            return "angle_to_median";
    }
    return "";
}

std::optional<OutlierFilter> outlier_filter_from_name(std::string_view name) {
    if (name.empty()) return OutlierFilter::none;
    for (OutlierFilter f : kOutlierFilterOrder)
        if (outlier_filter_name(f) == name) return f;
    return std::nullopt;
}

double periodic_difference(double a, double b, double period) {
    const double d = a - b;
    if (period <= 0) return d;
    // Into (−period/2, period/2].
    double r = std::remainder(d, period);  // [−period/2, period/2]
    if (r <= -period / 2) r += period;
    return r;
}

OutlierResult filter_outliers(std::span<const KeypointMatch> matches,
                              const OutlierParameters& parameters) {
    validate(parameters);
    for (std::size_t i = 0; i < matches.size(); ++i) check_finite(i, matches[i]);
    std::map<int, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < matches.size(); ++i) groups[matches[i].segment].push_back(i);

    OutlierResult result;
    result.removed_by.assign(matches.size(), OutlierFilter::none);
    for (auto& [segment, kept] : groups) {
        SegmentFilterLog log;
        log.segment = segment;
        for (OutlierFilter filter : kOutlierFilterOrder)
            log.steps.push_back(run_filter(filter, matches, kept, result.removed_by, parameters));
        result.segments.push_back(std::move(log));
    }
    return result;
}

}  // namespace tlsmon::keypoints
