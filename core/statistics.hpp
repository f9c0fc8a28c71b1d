#pragma once
// Order statistics of a sample, one definition for every method: quantiles, the median (and
// its "high" variant that is always a sample value), the median absolute deviation.
#include <span>
#include <vector>

namespace tlsmon {

// σ of normally distributed values from their median absolute deviation: σ ≈ 1.4826·MAD
// (1.4826 = 1/Φ⁻¹(3/4); Rousseeuw & Croux 1993).
inline constexpr double kMadToSigma = 1.4826;

// Linear interpolation between the order statistics of sorted values at position (n − 1)·q
// (Hyndman & Fan 1996, definition 7; R's and NumPy's default). NaN for no values.
double quantile_of_sorted(std::span<const double> sorted, double q);

// The median: the middle value, for an even count the mean of the two middle ones, computed
// as quantile_of_sorted(·, 0.5) computes it, so both give the same bits. NaN for no values.
double median(std::vector<double> values);

// The upper of the two middle values for an even count (the middle one for an odd count):
// always one of the values. NaN for no values.
double median_high(std::vector<double> values);

// The median (as median()) and the median absolute deviation about it (unscaled; see
// kMadToSigma). NaN for both without values.
struct MedianAndMad {
    double median;
    double mad;
};
MedianAndMad median_and_mad(std::vector<double> values);

}  // namespace tlsmon
