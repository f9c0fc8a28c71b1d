#include "algorithms/registration/distribution_quantiles.hpp"

#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tlsmon::registration {
namespace {

// Regularised incomplete gamma functions P(a, x) and Q(a, x) = 1 − P(a, x): the series for
// x < a + 1 and the continued fraction (modified Lentz) otherwise, as in Press et al.,
// "Numerical Recipes", 3rd ed. 2007, §6.2, eqs. 6.2.5 and 6.2.7.
double gamma_series_p(double a, double x) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < 10000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

double gamma_continued_fraction_q(double a, double x) {
    constexpr double tiny = 1e-300;
    double b = x + 1.0 - a;
    double c = 1.0 / tiny;
    double d = 1.0 / b;
    double h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

void check_dof(double dof) {
    if (!(dof > 0.0) || !std::isfinite(dof))
        throw Error("chi-square distribution: degrees of freedom must be > 0, got " +
                    std::to_string(dof));
}

void check_probability(double p, const char* what) {
    if (!(p > 0.0 && p < 1.0))
        throw Error(std::string(what) + ": probability must lie in (0, 1), got " +
                    std::to_string(p));
}

}  // namespace

double normal_cdf(double x) {
    return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

double normal_quantile(double p) {
    check_probability(p, "normal quantile");
    // Bisection on the monotone Φ: 200 halvings of [−40, 40] reach double precision.
    double lo = -40.0, hi = 40.0;
    for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
        const double mid = 0.5 * (lo + hi);
        // Compare in the smaller tail, where erfc keeps its relative precision.
        const bool below =
            p < 0.5 ? normal_cdf(mid) < p : 0.5 * std::erfc(mid / std::sqrt(2.0)) > 1.0 - p;
        (below ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double chi_square_cdf(double x, double dof) {
    check_dof(dof);
    if (x <= 0.0) return 0.0;
    const double a = 0.5 * dof, y = 0.5 * x;
    return y < a + 1.0 ? gamma_series_p(a, y) : 1.0 - gamma_continued_fraction_q(a, y);
}

double chi_square_upper_tail(double x, double dof) {
    check_dof(dof);
    if (x <= 0.0) return 1.0;
    const double a = 0.5 * dof, y = 0.5 * x;
    return y < a + 1.0 ? 1.0 - gamma_series_p(a, y) : gamma_continued_fraction_q(a, y);
}

double student_t_quantile(double p, double dof) {
    if (!(p > 0.0 && p < 1.0) || !(dof > 0.0))
        throw Error("Student's t quantile: needs 0 < p < 1 and dof > 0, got p = " +
                    std::to_string(p) + ", dof = " + std::to_string(dof));
    return boost::math::quantile(boost::math::students_t(dof), p);
}

double chi_square_quantile(double p, double dof) {
    check_dof(dof);
    check_probability(p, "chi-square quantile");
    double lo = 0.0, hi = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
    while (chi_square_cdf(hi, dof) < p) hi *= 2.0;
    for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        // The upper tail for p near 1, where 1 − cdf would lose its digits.
        const bool below =
            p < 0.5 ? chi_square_cdf(mid, dof) < p : chi_square_upper_tail(mid, dof) > 1.0 - p;
        (below ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double noncentral_chi_square_cdf(double x, double dof, double lambda) {
    check_dof(dof);
    if (x <= 0.0) return 0.0;
    if (lambda <= 0.0) return chi_square_cdf(x, dof);
    const double h = 0.5 * lambda;
    // Poisson weights from j = 0; past the mode (j > λ/2) they fall faster than geometrically,
    // so the sum stops once a weight is negligible.
    double sum = 0.0;
    for (int j = 0; j < 100000; ++j) {
        const double w = std::exp(-h + j * std::log(h) - std::lgamma(j + 1.0));
        sum += w * chi_square_cdf(x, dof + 2.0 * j);
        if (j > h && w < 1e-17) break;
    }
    return sum;
}

double detectable_noncentrality(double alpha, double power, double dof) {
    check_probability(alpha, "detectable noncentrality");
    check_probability(power, "detectable noncentrality");
    const double critical = chi_square_quantile(1.0 - alpha, dof);
    // The rejection probability 1 − F(crit; dof, λ) grows with λ: bisection.
    double lo = 0.0, hi = 10.0;
    while (1.0 - noncentral_chi_square_cdf(critical, dof, hi) < power) hi *= 2.0;
    for (int i = 0; i < 200 && hi - lo > 1e-10 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (1.0 - noncentral_chi_square_cdf(critical, dof, mid) < power ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace tlsmon::registration
