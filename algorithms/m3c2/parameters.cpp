#include "algorithms/m3c2/parameters.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tlsmon::m3c2 {

namespace {

void require_positive(double value, const char* name) {
    if (!(std::isfinite(value) && value > 0.0))
        throw Error(std::string("m3c2: ") + name + " must be a positive length in metres, not " +
                    std::to_string(value));
}

}  // namespace

NormalParameters normal_parameters(const Parameters& p, const Eigen::Vector3d& scanner) {
    return {p.normal_radii, p.orient_to_scanner ? Orientation::towards(scanner)
                                                : Orientation::along(p.orientation)};
}

CylinderParameters cylinder_parameters(const Parameters& p) {
    return {p.cylinder_radius, p.max_depth, p.statistic, p.stray_distance};
}

DistanceParameters distance_parameters(const Parameters& p) {
    return {static_cast<std::size_t>(p.min_points), p.registration_error, p.max_roughness};
}

void validate(const NormalParameters& p) {
    if (p.radii.empty()) throw Error("m3c2: normal_radii needs at least one radius");
    for (double r : p.radii) require_positive(r, "normal_radii");
    if (!p.orientation.value.allFinite())
        throw Error("m3c2: the orientation vector or position must be finite");
    if (p.orientation.kind == Orientation::Kind::vector && p.orientation.value.norm() == 0.0)
        throw Error("m3c2: the orientation vector must not be zero");
}

void validate(const CylinderParameters& p) {
    require_positive(p.radius, "cylinder_radius");
    require_positive(p.max_depth, "max_depth");
    if (!(p.stray_distance > 0.0))
        throw Error("m3c2: stray_distance must be a positive length in metres, not " +
                    std::to_string(p.stray_distance));
}

void validate(const DistanceParameters& p) {
    // The sample spread divides by n - 1: one point has none.
    if (p.min_points < 2)
        throw Error("m3c2: min_points must be at least 2 (a spread needs two points), not " +
                    std::to_string(p.min_points));
    if (!(std::isfinite(p.registration_error) && p.registration_error >= 0.0))
        throw Error("m3c2: registration_error must be a length >= 0 in metres, not " +
                    std::to_string(p.registration_error));
    if (!(p.max_reference_spread > 0.0))
        throw Error("m3c2: max_reference_spread must be a positive length in metres, not " +
                    std::to_string(p.max_reference_spread));
}

}  // namespace tlsmon::m3c2
