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
    if (values.size() != sampling_sigma.size())
        throw Error("zone uncertainty: " + std::to_string(values.size()) + " values for " +
                    std::to_string(sampling_sigma.size()) + " sampling σ");
    std::vector<std::size_t> first(values.size() + 1);
    std::iota(first.begin(), first.end(), std::size_t{0});
    return median_sampling_variance(values, first, sampling_sigma);
}

double median_sampling_variance(std::span<const double> values, std::span<const std::size_t> first,
                                std::span<const double> member_sigma) {
    const std::size_t members = member_sigma.size();
    if (first.size() != members + 1 || first.front() != 0 || first.back() != values.size() ||
        !std::is_sorted(first.begin(), first.end()))
        throw Error("zone uncertainty: " + std::to_string(first.size()) + " member bounds for " +
                    std::to_string(members) + " members of " + std::to_string(values.size()) +
                    " values");
    std::vector<std::size_t> member_of(values.size());
    for (std::size_t j = 0; j < members; ++j) {
        if (!(member_sigma[j] >= 0) || !std::isfinite(member_sigma[j]))
            throw Error("zone uncertainty: member " + std::to_string(j) +
                        " has a negative or non-finite sampling σ");
        std::fill(member_of.begin() + std::ptrdiff_t(first[j]),
                  member_of.begin() + std::ptrdiff_t(first[j + 1]), j);
    }
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
            throw Error("zone uncertainty: value " + std::to_string(i) + " is not finite");
    const std::size_t n = values.size();
    if (n == 0) return 0;
    // The middle value(s): the median is the middle one, or the mean of the middle two; alone,
    // it would err by its (their) member's σ.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto by_value = [&](std::size_t a, std::size_t b) { return values[a] < values[b]; };
    const std::size_t k = (n - 1) / 2;
    std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(k), order.end(), by_value);
    const std::size_t lower = member_of[order[k]];
    double m = values[order[k]], alone = member_sigma[lower] * member_sigma[lower];
    if (n % 2 == 0) {
        const std::size_t upper_value =
            *std::min_element(order.begin() + std::ptrdiff_t(k) + 1, order.end(), by_value);
        const std::size_t upper = member_of[upper_value];
        m = (m + values[upper_value]) / 2;
        if (upper != lower) alone = (alone + member_sigma[upper] * member_sigma[upper]) / 4;
    }
    // Per member, the count of its values ≤ m moves as one with its error e_j: with
    // P_c = P(e_j ≤ m − t_c), var(Σ_c 1[e_j ≤ m − t_c]) = Σ_{c,c'} P_min(c,c') − (Σ_c P_c)²,
    // the double sum taken over the P_c in ascending order (the i-th is the smaller of
    // 2(n_j − i) − 1 ordered pairs).
    double count_variance = 0, density = 0, weighted_s2 = 0;
    std::vector<double> P;
    for (std::size_t j = 0; j < members; ++j) {
        const double s = member_sigma[j];
        const std::size_t nj = first[j + 1] - first[j];
        weighted_s2 += double(nj) * double(nj) * s * s;
        if (s == 0 || nj == 0) continue;
        // The kernel: κσ_j for a member whose values lie together, σ_j for one whose values
        // spread by σ_j or more (header).
        double mean_v = 0, var_v = 0;
        for (std::size_t c = first[j]; c < first[j + 1]; ++c) mean_v += values[c];
        mean_v /= double(nj);
        for (std::size_t c = first[j]; c < first[j + 1]; ++c)
            var_v += (values[c] - mean_v) * (values[c] - mean_v);
        var_v /= double(nj);
        const double h = std::sqrt(kKernelWidth * kKernelWidth * s * s +
                                   (1 - kKernelWidth * kKernelWidth) * std::min(s * s, var_v));
        P.clear();
        double sum_P = 0;
        for (std::size_t c = first[j]; c < first[j + 1]; ++c) {
            const double z = (m - values[c]) / h;
            P.push_back(0.5 * std::erfc(-z / std::numbers::sqrt2));
            sum_P += P.back();
            density += std::exp(-0.5 * z * z) / (h * std::sqrt(2 * std::numbers::pi));
        }
        std::sort(P.begin(), P.end());
        double pairs = 0;
        for (std::size_t i = 0; i < nj; ++i) pairs += P[i] * double(2 * (nj - i) - 1);
        count_variance += std::max(0.0, pairs - sum_P * sum_P);
    }
    // Never below the form for equal true values, π/2 times the variance of the mean of the
    // values: where the values spread less than their σ says (a surface's relief in σ_s
    // cancels in d) the kernel estimate would fall below it. In a gap between values the
    // count's slope vanishes and the linearisation fails; there the middle values decide alone.
    const double equal = std::numbers::pi / 2 * weighted_s2 / (double(n) * double(n));
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
