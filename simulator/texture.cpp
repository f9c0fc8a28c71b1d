#include "simulator/texture.hpp"

#include <algorithm>
#include <cmath>

#include "simulator/random.hpp"

namespace tlsmon::sim {

namespace {

double lattice(std::uint64_t seed, std::int64_t i, std::int64_t j) {
    const std::uint64_t h = hash_combine(hash_combine(seed, static_cast<std::uint64_t>(i)),
                                         static_cast<std::uint64_t>(j));
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double smoothstep(double x) {
    return x * x * (3.0 - 2.0 * x);
}

// Sum of octaves of value noise, normalised to about [-0.5, 0.5].
double octaves(std::uint64_t seed, double u, double v, double base_scale, int count) {
    double sum = 0.0, norm = 0.0, amplitude = 1.0, scale = base_scale;
    for (int k = 0; k < count; ++k) {
        sum += amplitude * (value_noise(hash_combine(seed, k), u / scale, v / scale) - 0.5);
        norm += amplitude;
        amplitude *= 0.55;
        scale *= 0.5;
    }
    return sum / norm;
}

// Distance of x to the nearest multiple of `period`.
double to_grid(double x, double period) {
    const double r = x - period * std::floor(x / period);
    return std::min(r, period - r);
}

// The share of a Gaussian (σ = blur) centred at distance d from the middle of a strip of
// width w that falls on the strip: ½ [erf((d + w/2)/√2σ) − erf((d − w/2)/√2σ)];
// the strip's indicator for blur 0.
double on_strip(double d, double w, double blur) {
    if (blur <= 0.0) return d < 0.5 * w ? 1.0 : 0.0;
    const double k = 1.0 / (std::sqrt(2.0) * blur);
    return 0.5 * (std::erf((d + 0.5 * w) * k) - std::erf((d - 0.5 * w) * k));
}

// The same for a disc of radius R at distance ρ from its centre, approximated by the
// blurred edge ½ erfc((ρ − R)/√2σ) (the exact share is a Marcum Q function; the
// approximation is within a few per cent for σ up to R/2).
double on_disc(double rho, double radius, double blur) {
    if (blur <= 0.0) return rho < radius ? 1.0 : 0.0;
    return 0.5 * std::erfc((rho - radius) / (std::sqrt(2.0) * blur));
}

}  // namespace

double value_noise(std::uint64_t seed, double u, double v) {
    const double fu = std::floor(u), fv = std::floor(v);
    const auto i = static_cast<std::int64_t>(fu);
    const auto j = static_cast<std::int64_t>(fv);
    const double a = smoothstep(u - fu), b = smoothstep(v - fv);
    const double v00 = lattice(seed, i, j), v10 = lattice(seed, i + 1, j);
    const double v01 = lattice(seed, i, j + 1), v11 = lattice(seed, i + 1, j + 1);
    return (v00 * (1 - a) + v10 * a) * (1 - b) + (v01 * (1 - a) + v11 * a) * b;
}

double concrete_albedo(const Texture& t, int face, double u, double v, double blur) {
    const std::uint64_t seed = hash_combine(t.seed, static_cast<std::uint64_t>(face) + 1);
    // Patches and weathering (metres) and fine aggregate (centimetres).
    double a = t.albedo * (1.0 + 0.35 * octaves(seed, u, v, 3.0, 4) +
                           0.25 * octaves(hash_combine(seed, 99), u, v, 0.08, 3));
    // Run-off stains: dark vertical streaks, strongest below panel joints, fading downwards.
    const double streak = value_noise(hash_combine(seed, 7), u / 0.35, 0.0);
    const double fade = value_noise(hash_combine(seed, 8), u / 1.5, v / 6.0);
    if (streak > 0.62) a *= 1.0 - 0.9 * (streak - 0.62) * fade;
    // Formwork joints: thin dark lines on the panel grid, offset per face. The share of the
    // (blurred) point on a joint: the union of a vertical and a horizontal strip, whose
    // blur is exact because the Gaussian is separable: 1 − (1 − J_u)(1 − J_v).
    const double pu = u + 0.37 * face;
    const double ju = on_strip(to_grid(pu, t.panel_width), t.joint_width, blur);
    const double jv = on_strip(to_grid(v, t.panel_height), t.joint_width, blur);
    a *= 1.0 - 0.45 * (1.0 - (1.0 - ju) * (1.0 - jv));
    // Tie holes: dark discs at the quarter points of each panel, half-way up.
    const double cu = t.panel_width / 4.0, cv = t.panel_height / 2.0;
    const double du = to_grid(pu - cu, t.panel_width / 2.0);
    const double dv = to_grid(v - cv, t.panel_height);
    a *= 1.0 - 0.75 * on_disc(std::hypot(du, dv), t.tie_hole_radius, blur);
    return std::clamp(a, 0.02, 1.0);
}

double checkerboard_albedo(double a, double b, double blur) {
    constexpr double mean = 0.5 * (kCheckerWhite + kCheckerBlack);
    constexpr double half = 0.5 * (kCheckerWhite - kCheckerBlack);
    if (blur <= 0.0) return (a >= 0.0) == (b >= 0.0) ? kCheckerWhite : kCheckerBlack;
    const double k = 1.0 / (std::sqrt(2.0) * blur);
    return mean + half * std::erf(a * k) * std::erf(b * k);
}

double ground_albedo(const Texture& t, double x, double y) {
    const std::uint64_t seed = hash_combine(t.seed, 0x67726f756e64ULL);
    const double a = 0.30 * (1.0 + 0.6 * octaves(seed, x, y, 4.0, 4) +
                             0.3 * octaves(hash_combine(seed, 5), x, y, 0.15, 2));
    return std::clamp(a, 0.03, 1.0);
}

}  // namespace tlsmon::sim
