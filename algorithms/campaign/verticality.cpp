#include "algorithms/campaign/verticality.hpp"

#include <cmath>
#include <limits>

#include "algorithms/campaign/local_plane.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {

const char* class_name(VerticalityClass c) {
    switch (c) {
        case VerticalityClass::vertical:
            return "vertical";
        case VerticalityClass::horizontal:
            return "horizontal";
        case VerticalityClass::other:
            return "other";
        case VerticalityClass::undefined:
            break;
    }
    return "undefined";
}

VerticalityClass classify(double v, const VerticalityParameters& p) {
    if (!std::isfinite(v)) return VerticalityClass::undefined;
    if (v >= p.vertical_min) return VerticalityClass::vertical;
    if (v <= p.horizontal_max) return VerticalityClass::horizontal;
    return VerticalityClass::other;
}

void validate(const VerticalityParameters& p) {
    if (!(p.radius > 0 && p.radius <= 100)) throw Error("campaign: radius must lie in (0, 100] m");
    if (p.min_neighbours < 3) throw Error("campaign: min_neighbours must be at least 3");
    if (!(p.horizontal_max >= 0 && p.horizontal_max < p.vertical_min && p.vertical_min <= 1))
        throw Error("campaign: need 0 ≤ horizontal_max < vertical_min ≤ 1");
}

std::vector<float> verticality(std::span<const Eigen::Vector3d> points,
                               const VerticalityParameters& p, unsigned threads) {
    validate(p);
    const std::vector<LocalPlane> planes =
        local_planes(points, p.radius, p.min_neighbours, threads);
    std::vector<float> out(points.size(), std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < planes.size(); ++i)
        if (planes[i].defined()) out[i] = 1.0f - std::abs(planes[i].normal.z());
    return out;
}

}  // namespace tlsmon::campaign
