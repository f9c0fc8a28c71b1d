#include "algorithms/m3c2/zone_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace tlsmon::m3c2 {

namespace {

// The kernel's width over σ_i at which equal true values give the median's π σ²/(2n)
// (zone_uncertainty.hpp).
constexpr double kKernelWidth = 0.8257;

// Throws unless every value is finite and every σ finite and ≥ 0, one σ per value.
void check_members(std::span<const double> values, std::span<const double> sigma,
                   const char* what) {
    if (values.size() != sigma.size())
        throw Error("zone uncertainty: " + std::to_string(values.size()) + " values for " +
                    std::to_string(sigma.size()) + " " + what);
    for (std::size_t i = 0; i < sigma.size(); ++i)
        if (!std::isfinite(values[i]) || !(sigma[i] >= 0) || !std::isfinite(sigma[i]))
            throw Error("zone uncertainty: member " + std::to_string(i) +
                        " has a non-finite value or a negative or non-finite " + what);
}

}  // namespace

double median_sampling_variance(std::span<const double> values,
                                std::span<const double> sampling_sigma) {
    check_members(values, sampling_sigma, "sampling σ");
    const std::size_t n = values.size();
    if (n == 0) return 0;
    // The middle member(s): the median is the middle one's value, or the mean of the middle
    // two's; alone, it would err by its (their) σ.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto by_value = [&](std::size_t a, std::size_t b) { return values[a] < values[b]; };
    const std::size_t k = (n - 1) / 2;
    std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(k), order.end(), by_value);
    const std::size_t lower = order[k];
    double m = values[lower], alone = sampling_sigma[lower] * sampling_sigma[lower];
    if (n % 2 == 0) {
        const std::size_t upper =
            *std::min_element(order.begin() + std::ptrdiff_t(k) + 1, order.end(), by_value);
        m = (m + values[upper]) / 2;
        alone = (alone + sampling_sigma[upper] * sampling_sigma[upper]) / 4;
    }
    double count_variance = 0, density = 0, sum_s2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double s = sampling_sigma[i];
        sum_s2 += s * s;
        if (s == 0) continue;
        const double h = kKernelWidth * s, z = (m - values[i]) / h;
        const double F = 0.5 * std::erfc(-z / std::numbers::sqrt2);
        count_variance += F * (1 - F);
        density += std::exp(-0.5 * z * z) / (h * std::sqrt(2 * std::numbers::pi));
    }
    // Never below the form for equal true values: where the distances spread less than their
    // σ says (a surface's relief in σ_s cancels in d) the kernel estimate would fall below it.
    // In a gap between members the count's slope vanishes and the linearisation fails; there
    // the middle members decide alone.
    const double equal = std::numbers::pi / 2 * (sum_s2 / double(n)) / double(n);
    const double linearised = density > 0 ? count_variance / (density * density)
                                          : std::numeric_limits<double>::infinity();
    return std::max(std::min(linearised, alone), equal);
}

ZoneUncertainty zone_uncertainty(std::span<const double> values,
                                 std::span<const double> sampling_sigma,
                                 std::span<const double> registration_sigma, double cylinder_radius,
                                 double core_spacing) {
    if (!(cylinder_radius > 0) || !(core_spacing > 0))
        throw Error("zone uncertainty: the cylinder radius and the core spacing must be > 0");
    return aggregate_uncertainty(
        values, sampling_sigma, registration_sigma,
        std::max(1.0, std::numbers::pi * cylinder_radius * cylinder_radius /
                          (core_spacing * core_spacing)));
}

ZoneUncertainty aggregate_uncertainty(std::span<const double> values,
                                      std::span<const double> sampling_sigma,
                                      std::span<const double> registration_sigma, double overlap) {
    check_members(values, sampling_sigma, "sampling σ");
    check_members(values, registration_sigma, "registration σ");
    if (!(overlap >= 1)) throw Error("zone uncertainty: the overlap must be >= 1");
    ZoneUncertainty u;
    u.n = sampling_sigma.size();
    if (u.n == 0) return u;
    double sum_s2 = 0, sum_reg = 0;
    for (std::size_t i = 0; i < u.n; ++i) {
        sum_s2 += sampling_sigma[i] * sampling_sigma[i];
        sum_reg += registration_sigma[i];
    }
    const double n = static_cast<double>(u.n);
    u.overlap = overlap;
    const double mean_variance = u.overlap * (sum_s2 / n) / n;
    const double median_variance = u.overlap * median_sampling_variance(values, sampling_sigma);
    u.sampling_mean = std::sqrt(mean_variance);
    u.sampling_median = std::sqrt(median_variance);
    u.registration = sum_reg / n;
    const double reg2 = u.registration * u.registration;
    u.mean_sigma = std::sqrt(mean_variance + reg2);
    u.median_sigma = std::sqrt(median_variance + reg2);
    return u;
}

}  // namespace tlsmon::m3c2
