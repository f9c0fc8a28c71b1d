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

double concrete_albedo(const Texture& t, int face, double u, double v) {
    const std::uint64_t seed = hash_combine(t.seed, static_cast<std::uint64_t>(face) + 1);
    // Patches and weathering (metres) and fine aggregate (centimetres).
    double a = t.albedo * (1.0 + 0.35 * octaves(seed, u, v, 3.0, 4) +
                           0.25 * octaves(hash_combine(seed, 99), u, v, 0.08, 3));
    // Run-off stains: dark vertical streaks, strongest below panel joints, fading downwards.
    const double streak = value_noise(hash_combine(seed, 7), u / 0.35, 0.0);
    const double fade = value_noise(hash_combine(seed, 8), u / 1.5, v / 6.0);
    if (streak > 0.62) a *= 1.0 - 0.9 * (streak - 0.62) * fade;
    // Formwork joints: thin dark lines on the panel grid, offset per face.
    const double pu = u + 0.37 * face;
    if (to_grid(pu, t.panel_width) < 0.5 * t.joint_width ||
        to_grid(v, t.panel_height) < 0.5 * t.joint_width) {
        a *= 0.55;
    }
    // Tie holes: dark discs at the quarter points of each panel, half-way up.
    const double cu = t.panel_width / 4.0, cv = t.panel_height / 2.0;
    const double du = to_grid(pu - cu, t.panel_width / 2.0);
    const double dv = to_grid(v - cv, t.panel_height);
    if (du * du + dv * dv < t.tie_hole_radius * t.tie_hole_radius) a *= 0.25;
    return std::clamp(a, 0.02, 1.0);
}

double ground_albedo(const Texture& t, double x, double y) {
    const std::uint64_t seed = hash_combine(t.seed, 0x67726f756e64ULL);
    const double a = 0.30 * (1.0 + 0.6 * octaves(seed, x, y, 4.0, 4) +
                             0.3 * octaves(hash_combine(seed, 5), x, y, 0.15, 2));
    return std::clamp(a, 0.03, 1.0);
}

}  // namespace tlsmon::sim
