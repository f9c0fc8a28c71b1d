#pragma once
// The sun as it heats a structure: its position, clear-sky irradiance on vertical faces, and
// the first-order lag through which a body's temperature follows its drive. Shared by the
// simulator (which heats its pier with them) and the thermal compensation (which uses them as
// regressors, docs/thermal.md).
#include <array>

namespace tlsmon {

// Approximate sun position (Spencer 1971 declination and equation of time, as in NOAA's
// "General Solar Position Calculations"): about 0.1° and 1 min, ample for heating.
struct SunPosition {
    double elevation_deg = 0.0;
    double azimuth_deg = 0.0;  // from north, clockwise (east 90°)
    double declination_deg = 0.0;
    double solar_hour = 0.0;  // local apparent solar time, 0..24
};
SunPosition sun_position(double latitude_deg, double longitude_deg, double unix_seconds);

// Local apparent solar time of sunrise (sun's upper limb at the horizon with refraction,
// h₀ = −0.833°); 0 in polar day, 12 in polar night.
double sunrise_solar_hour(double latitude_deg, double declination_deg);

// Day of the year (1 = 1 January, UTC) of a time.
double day_of_year(double unix_seconds);

// Vertical faces by their outward normals: west (−x), east (+x), south (−y), north (+y),
// project frame x east, y north.
constexpr std::array<const char*, 4> kFaceNames = {"west", "east", "south", "north"};

// Clear-sky solar irradiance incident on the four vertical faces, W/m²: relative air mass
// (Kasten & Young 1989), direct normal irradiance 1353 W/m² · 0.7^(AM^0.678) (Meinel & Meinel
// 1976), and on a vertical face half the sky of a diffuse horizontal irradiance of 10 % of the
// beam's. Zero with the sun below the horizon.
std::array<double, 4> clear_sky_face_irradiance(const SunPosition& sun);

// One step h of dy/dt = (x − y)/τ with x linear from x0 to x1 over the step (exact for that
// input); τ ≤ 0 follows the input without lag.
double lag_step(double y, double x0, double x1, double h, double tau);

}  // namespace tlsmon
