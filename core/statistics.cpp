#include "core/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tlsmon {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double quantile_of_sorted(std::span<const double> sorted, double q) {
    if (sorted.empty()) return kNaN;
    const double h = static_cast<double>(sorted.size() - 1) * q;
    const auto below = static_cast<std::size_t>(std::floor(h));
    if (below + 1 >= sorted.size()) return sorted.back();
    return sorted[below] + (h - static_cast<double>(below)) * (sorted[below + 1] - sorted[below]);
}

// A partial sort (nth_element) instead of a sort: O(n). For an even count the lower middle
// value is the largest of the half below the upper one.
double median(std::vector<double> values) {
    const std::size_t n = values.size();
    if (n == 0) return kNaN;
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(values.begin(), middle, values.end());
    const double upper = *middle;
    if (n % 2 == 1) return upper;
    const double lower = *std::max_element(values.begin(), middle);
    return lower + 0.5 * (upper - lower);  // as quantile_of_sorted at q = 0.5
}

double median_high(std::vector<double> values) {
    if (values.empty()) return kNaN;
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
}

MedianAndMad median_and_mad(std::vector<double> values) {
    if (values.empty()) return {kNaN, kNaN};
    const double centre = median(values);
    for (double& v : values) v = std::abs(v - centre);
    return {centre, median(std::move(values))};
}

}  // namespace tlsmon
