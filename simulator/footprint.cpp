#include "simulator/footprint.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tlsmon::sim {

const std::array<SubRay, kSubRays>& footprint_pattern() {
    static const std::array<SubRay, kSubRays> pattern = [] {
        std::array<SubRay, kSubRays> p{};
        p[0] = {0.0, 0.0, 0.5};
        for (std::size_t k = 1; k < kSubRays; ++k) {
            // Hexagon at ρ = w, rotated by 30° so no sub-ray lies on the grid's axes.
            const double a = (30.0 + 60.0 * static_cast<double>(k - 1)) * std::numbers::pi / 180.0;
            p[k] = {std::cos(a), std::sin(a), 0.5 / 6.0};
        }
        return p;
    }();
    return pattern;
}

double footprint_radius(const Beam& beam, double range) {
    return 0.5 * (beam.exit_diameter + beam.divergence_mrad * 1e-3 * std::max(range, 0.0));
}

double footprint_angle(const Beam& beam, double range) {
    return footprint_radius(beam, range) / std::max(range, 1e-3);
}

}  // namespace tlsmon::sim
