#pragma once
// The outlier filters of the keypoint method (Hochmoselbrücke case study, step 5): per
// segment, in this order, each on the matches the previous ones kept, a match is removed
// when its value x of the filter's quantity lies farther from the segment's median than
// k · 1.4826 · MAD (k = 2; 1.4826 · MAD estimates σ for normally distributed values):
//
//   row_difference               row − reference_row (image rows, vertical angle steps)
//   column_difference            column − reference_column (wrapped when the image spans a
//                                full turn of `columns_per_turn` columns)
//   range_difference             range − reference_range (m)
//   horizontal_angle_difference  azimuth − reference_azimuth, wrapped into (−π, π] (rad)
//   vertical_angle_difference    elevation − reference_elevation (rad)
//   dx, dy, dz                   the displacement's components in the project frame (m)
//   magnitude                    |displacement| (m)
//   angle_to_median              the angle between the displacement and the median vector
//                                (the component-wise median of the kept displacements), rad
//
// The angle filter removes only angles above the median + threshold: a small angle is
// agreement with the median direction (two-sided, the rule would discard the vectors most
// parallel to it whenever the angles' median lies more than the threshold above 0).
// These names are stable: they are the `removed_by` column of `tlsmon keypoints`. Rules for
// the cases the formula leaves open (docs/keypoints.md):
// - MAD = 0 (more than half the values equal, e.g. whole-pixel row differences): the rule
//   as written would remove every value off the median. The robust σ falls back to
//   1.2533 · the mean absolute deviation from the median (√(π/2), consistent for the
//   normal distribution), which stays above zero when any value differs and still
//   singles out gross outliers; when that is zero too (all values equal) nothing is removed.
// - A spread below the measurement noise (two packagings of one scan: the vectors agree to
//   micrometres, MAD ≈ 0 but not 0, and the rule would remove all but the median's
//   neighbours): with the scanner's stochastic model given (`noise`), σ is never taken below
//   the noise of a difference of two measurements, √2 · the single measurement's σ, at the
//   segment's median range: σ_r for the range, σ_θ for the angles (σ_θ / step in pixels),
//   max(σ_r, r·σ_θ) for the vector's components and length, that over |median vector| for
//   the angle to the median — each divided by √m, m the pixels a match's position is
//   estimated from (`averaged_pixels`: the refinement's patch), since a least-squares
//   match over m pixels is √m times more precise than one of them. A floor, not a σ: it
//   must lie below every real spread (on the `pier` series 0.14 mm against vectors that
//   scatter by 0.8 mm). `floored` says when the floor set the threshold.
// - Fewer than `min_matches` kept (default 3, the fewest where one value can stand out):
//   the filter is skipped.
// - angle_to_median: skipped when the median vector is zero; a zero displacement has no
//   direction and is kept by this filter.
// - Matches outside every segment (segment −1) are filtered as one group of their own.
// A non-finite value in a match is an error naming the match, never a silent NaN.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "algorithms/keypoints/keypoint_match.hpp"
#include "algorithms/keypoints/parameters.hpp"
#include "core/scanner_noise.hpp"

namespace tlsmon::keypoints {

enum class OutlierFilter : std::uint8_t {
    none,  // kept by every filter
    row_difference,
    column_difference,
    range_difference,
    horizontal_angle_difference,
    vertical_angle_difference,
    dx,
    dy,
    dz,
    magnitude,
    angle_to_median,
};

// The filters in the order they run.
inline constexpr std::array<OutlierFilter, 10> kOutlierFilterOrder{
    OutlierFilter::row_difference,
    OutlierFilter::column_difference,
    OutlierFilter::range_difference,
    OutlierFilter::horizontal_angle_difference,
    OutlierFilter::vertical_angle_difference,
    OutlierFilter::dx,
    OutlierFilter::dy,
    OutlierFilter::dz,
    OutlierFilter::magnitude,
    OutlierFilter::angle_to_median,
};

// The stable name ("" for none) and back; an unknown name gives nullopt.
std::string_view outlier_filter_name(OutlierFilter filter);
std::optional<OutlierFilter> outlier_filter_from_name(std::string_view name);

struct OutlierParameters {
    double k = Parameters{}.mad_k;  // threshold in robust standard deviations
    std::size_t min_matches = 3;    // fewer kept: the filter is skipped
    double columns_per_turn = 0;    // image columns in 360° (0: the image does not wrap)
    // The noise floor of σ (header); none: the spread alone.
    std::optional<ScannerNoise> noise;
    // rad per pixel of each structured scan (KeypointMatch::scan), for the floor of the row
    // and column differences; a scan without an entry has no floor there.
    std::vector<double> angular_steps;
    double averaged_pixels = 1;  // pixels a match's position is estimated from (≥ 1)
};

// What one filter did in one segment.
struct FilterStep {
    OutlierFilter filter = OutlierFilter::none;
    std::size_t tested = 0;  // matches it looked at (kept by the filters before it)
    std::size_t removed = 0;
    bool skipped = false;  // too few matches, all values equal, or a zero median vector
    double median = 0;     // of the quantity over the tested matches
    double mad = 0;        // median absolute deviation from it (unscaled)
    double sigma = 0;      // 1.4826 · MAD, or 1.2533 · mean absolute deviation if MAD = 0
    bool mad_was_zero = false;
    double floor = 0;      // the noise floor of σ (0: none)
    bool floored = false;  // σ was raised to the floor
    double threshold = 0;  // k · sigma
};

struct SegmentFilterLog {
    int segment = -1;
    std::vector<FilterStep> steps;  // in kOutlierFilterOrder
};

struct OutlierResult {
    std::vector<OutlierFilter> removed_by;   // per match, in the input's order
    std::vector<SegmentFilterLog> segments;  // ascending segment id
};

// The filters over every segment of `matches` (grouped by KeypointMatch::segment).
OutlierResult filter_outliers(std::span<const KeypointMatch> matches,
                              const OutlierParameters& parameters = {});

// a − b reduced into (−period/2, period/2]; period 0 leaves a − b as is.
double periodic_difference(double a, double b, double period);

}  // namespace tlsmon::keypoints
