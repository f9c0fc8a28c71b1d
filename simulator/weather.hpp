#pragma once
// The site's weather and the pier's face temperatures, as pure functions of the UTC time
// (docs/simulator.md, "Weather and temperature", has the equations with their sources).
//
// Air, in local apparent solar time h (UTC + λ/15° h + equation of time):
//   T(t)  = M(t) + A(t)·shape(h)      shape −1 at sunrise, +1 at `max_hour_solar`, two
//                                     half-cosines between them (periodic, continuous)
//   A(t)  = daily_range/2 · (1 − 0.6·c(t))   clouds damp the daily range
//   M, c and the pressure anomaly are daily values (at local solar noon) of seeded AR(1)
//   sequences, interpolated between noons by a half-cosine;
//   p(t)  = p̄ + σ_p·x_p + tide·cos(2π(h − 10)/12)   semidiurnal tide, maxima 10 h and 22 h
//   T_dew = M − A − (1 + 3·(1 − c))   a dew point below the daily minimum, closer when
//                                     cloudy; RH = 100·E(T_dew)/E(T)
// Faces (0 west, 1 east, 2 south, 3 north, outward normals −x, +x, −y, +y): the incident
// solar irradiance I_f (clear-sky beam and diffuse, damped by clouds), the sol-air
// temperature T + a·I_f/h_o, and the face temperature that follows it through a first-order
// lag τ_s; the section's side temperatures follow the faces through a second lag τ
// (deformation.time_constant_hours). Both lags are integrated from a spin-up of at least
// 48 h (and ten time constants) before the asked time, so a time's state never depends on
// which epoch was rendered first.
#include <array>
#include <cstdint>

#include "core/solar.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

// The scene's air at one time (no lag: what a weather station's sensors see).
struct AirSample {
    double temperature_c = 0.0;
    double pressure_hpa = 0.0;
    double relative_humidity_pct = 0.0;
    double dew_point_c = 0.0;
    double cloudiness = 0.0;  // 0 clear .. 1 overcast
    SunPosition sun;
};
AirSample air_at(const Weather& w, double unix_seconds);

// Solar irradiance incident on the pier's four vertical faces (kFaceNames), W/m²: the clear
// sky's (core/solar.hpp) damped by the clouds.
std::array<double, 4> face_irradiance(const SunPosition& sun, double cloudiness);

struct ThermalState {
    AirSample air;
    std::array<double, 4> irradiance{};  // W/m², now
    std::array<double, 4> sol_air_c{};   // T + a·I/h_o, now
    std::array<double, 4> face_c{};      // face surface temperatures (lag τ_s)
    std::array<double, 4> section_c{};   // the section's side temperatures (further lag τ)
    int sunlit_face = -1;                // face with the strongest sun; −1 at night
};

// The state at `unix_seconds`, integrated from the spin-up.
ThermalState thermal_state(const Site& site, double unix_seconds);

}  // namespace tlsmon::sim
