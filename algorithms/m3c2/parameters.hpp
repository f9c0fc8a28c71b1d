#pragma once
// The parameters of M3C2 (Lague, Brodu & Leroux 2013) as plain structs with defaults, in the
// paper's terms: normal scale(s) D/2, projection scale d/2, max depth h, registration error.
// Radii and half-lengths throughout (CloudCompare's dialog asks for diameters; see
// docs/m3c2.md for the mapping). `validate` names the offending parameter.
//
// `Parameters` is what a user sets, with its defaults in this one place: the site's [m3c2]
// section embeds it and `tlsmon m3c2` starts from it. The kernel's parts (normals,
// cylinders, distance) are derived from it.
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

// A stray must also lie this many robust σ (1.4826·MAD) from the cylinder's median, so that a
// rough surface's own relief is never cut: for normally distributed projections it leaves
// out 0.05 % of them (the clip of PB-M3C2's planes, algorithms/patches/patch_plane.hpp).
inline constexpr double kStrayRobustSigmas = 3.5;
// A cylinder whose strays are more than this share of its points holds two surfaces — a
// corner's other face, which in the next epoch may be the larger part and so the one kept —
// and has no centre: its core point gets no distance.
inline constexpr double kMaxStrayShare = 0.1;

// The statistic of the projections in a cylinder: mean with the sample standard deviation,
// or median with the interquartile range (Lague 2013, section 4.2, robust variant).
enum class CylinderStatistic { mean, median };

struct Parameters {
    double core_spacing = 0.5;                   // m, cubes of the core point subsampling
    std::vector<double> normal_radii{0.5, 1.0};  // m, the scales D/2 tried at each core point
    double cylinder_radius = 0.5;                // m, the projection scale d/2
    double max_depth = 1.0;                      // m, the cylinder's half-length h
    int min_points = 10;                         // per cylinder and cloud, else no distance
    bool orient_to_scanner = true;               // else along `orientation`
    Eigen::Vector3d orientation = Eigen::Vector3d::UnitZ();
    CylinderStatistic statistic = CylinderStatistic::mean;
    // m: a reference cylinder whose spread s1 (the roughness σ1 along the normal) exceeds
    // this holds more than one surface — an edge, a corner, clutter — and its mean depends
    // on which of them each epoch's sampling happens to catch: no distance (NaN). Infinity
    // keeps the method as published.
    double max_roughness = 0.02;
    // m: a cylinder's point farther than this from the median of its projections, and than
    // kStrayRobustSigmas robust σ of them, is a stray — the next face round a corner, a mixed
    // return behind an edge — and is left out of the mean and its spread. Infinity (or twice
    // max_depth or more) keeps the method as published.
    double stray_distance = 0.01;
    double registration_error = 0.0;  // m, "reg" of Lague 2013, eq. 1, without a registration
    int threads = 0;                  // 0: every core
};

struct NormalParameters {
    std::vector<double> radii = Parameters{}.normal_radii;
    Orientation orientation;
};

struct CylinderParameters {
    double radius = Parameters{}.cylinder_radius;
    double max_depth = Parameters{}.max_depth;
    CylinderStatistic statistic = Parameters{}.statistic;
    // Parameters::stray_distance; infinity (no clip) is the method as published, which the
    // kernel's known-answer tests check. The `median` statistic is robust without it.
    double stray_distance = std::numeric_limits<double>::infinity();
};

struct DistanceParameters {
    std::size_t min_points = static_cast<std::size_t>(Parameters{}.min_points);
    double registration_error = Parameters{}.registration_error;
    // m, Parameters::max_roughness; infinity (no limit) is the method as published, which
    // the kernel's known-answer tests check.
    double max_reference_spread = std::numeric_limits<double>::infinity();
};

// The kernel's parts of `p`; `scanner`: the position the normals face with orient_to_scanner.
NormalParameters normal_parameters(const Parameters& p, const Eigen::Vector3d& scanner);
CylinderParameters cylinder_parameters(const Parameters& p);
DistanceParameters distance_parameters(const Parameters& p);

// Throws Error naming the parameter when a value cannot give a meaningful result.
void validate(const NormalParameters& p);
void validate(const CylinderParameters& p);
void validate(const DistanceParameters& p);

}  // namespace tlsmon::m3c2
