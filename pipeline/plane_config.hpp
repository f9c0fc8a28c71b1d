#pragma once
// What the registration on the scene's own planes needs of the site (docs/configuration.md,
// [registration] plane_* keys and the scanner's noise of [station]; docs/registration.md,
// "Registration on planes").
#include <array>

#include "algorithms/registration/plane_detection.hpp"
#include "algorithms/registration/plane_matching.hpp"
#include "algorithms/registration/plane_registration.hpp"
#include "core/scanner_noise.hpp"

namespace tlsmon {

// The zone quantities of the registration on planes (each zone's plane series,
// pipeline/registration_rows.hpp): the tilt of the plane's normal towards its long axis u and
// towards v = n × u, its shift along the normal. The alarm rules name them.
inline constexpr const char* kPlaneTiltU = "plane_tilt_u_arcsec";
inline constexpr const char* kPlaneTiltV = "plane_tilt_v_arcsec";
inline constexpr const char* kPlaneShift = "plane_shift_m";
inline constexpr std::array<const char*, 3> kPlaneQuantities = {kPlaneTiltU, kPlaneTiltV,
                                                                kPlaneShift};

struct PlaneConfig {
    // The scanner's stochastic model, against which a block of the grid is planar: the
    // site's ([station], set by pipeline_config), not a key of its own.
    ScannerNoise noise;
    double flatness = 0.001;  // m, a real surface's own departure from a plane
    int min_points = 50;      // a plane has at least this many points
    double max_normal_sigma_arcsec = 60.0;
    // Datum-dependent matching from the approximate transformation.
    double max_angle_deg = 1.0;
    double max_offset = 0.05;  // m
    // The congruence test.
    double alpha = 0.05;
    int min_planes = 4;

    registration::PlaneDetectionParams detection() const {
        registration::PlaneDetectionParams p;
        p.noise = noise;
        p.flatness = flatness;
        p.min_points = static_cast<std::size_t>(min_points);
        p.max_normal_sigma_arcsec = max_normal_sigma_arcsec;
        return p;
    }
    registration::PlaneMatchingParams matching() const {
        registration::PlaneMatchingParams p;
        p.max_angle_deg = max_angle_deg;
        p.max_offset = max_offset;
        return p;
    }
    registration::CongruenceParams congruence() const {
        registration::CongruenceParams p;
        p.alpha = alpha;
        p.min_planes = static_cast<std::size_t>(min_planes);
        return p;
    }
};

}  // namespace tlsmon
