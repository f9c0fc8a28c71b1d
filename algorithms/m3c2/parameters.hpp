#pragma once
// The parameters of M3C2 (Lague, Brodu & Leroux 2013) as plain structs with defaults, in the
// paper's terms: normal scale(s) D/2, projection scale d/2, max depth h, registration error.
// Radii and half-lengths throughout (CloudCompare's dialog asks for diameters; see
// docs/m3c2.md for the mapping). `validate` names the offending parameter.
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <vector>

namespace tlsmon::m3c2 {

// Which way a normal points: n · v ≥ 0 for v a fixed vector, or for v = (position − c),
// the direction from the core point c towards a position (the scanner's).
struct Orientation {
    enum class Kind { vector, towards_position };
    Kind kind = Kind::vector;
    Eigen::Vector3d value = Eigen::Vector3d::UnitZ();

    static Orientation along(const Eigen::Vector3d& v) { return {Kind::vector, v}; }
    static Orientation towards(const Eigen::Vector3d& position) {
        return {Kind::towards_position, position};
    }
};

struct NormalParameters {
    std::vector<double> radii{0.05, 0.10, 0.20};  // m, the scales D/2 tried at each core point
    Orientation orientation;
};

// The statistic of the projections in a cylinder: mean with the sample standard deviation,
// or median with the interquartile range (Lague 2013, section 4.2, robust variant).
enum class CylinderStatistic { mean, median };

struct CylinderParameters {
    double radius = 0.05;     // m, the projection scale d/2
    double max_depth = 0.30;  // m, the cylinder's half-length h along the normal
    CylinderStatistic statistic = CylinderStatistic::mean;
};

struct DistanceParameters {
    std::size_t min_points = 5;       // fewer in either cylinder: no distance (NaN)
    double registration_error = 0.0;  // m, "reg" of Lague 2013, eq. 1
    // m: a reference cylinder whose spread s1 (the roughness σ1 along the normal) exceeds
    // this holds more than one surface — an edge, a corner, clutter — and its mean depends
    // on which of them each epoch's sampling happens to catch: no distance (NaN). The
    // default (infinity) keeps the method as published.
    double max_reference_spread = std::numeric_limits<double>::infinity();
};

// Throws Error naming the parameter when a value cannot give a meaningful result.
void validate(const NormalParameters& p);
void validate(const CylinderParameters& p);
void validate(const DistanceParameters& p);

}  // namespace tlsmon::m3c2
