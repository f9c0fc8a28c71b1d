#pragma once
// The drivers of a structure's thermal response at the epochs' times (docs/thermal.md,
// "Drivers"): the air temperature and the clear-sky solar irradiance on the four vertical
// faces, each passed through two first-order lags in series — the surface behind its drive
// (τ_s), the section behind its surface (τ) — as a concrete section's temperature follows the
// sol-air temperature (Kehlbeck 1975; Elbadry & Ghali 1983 reduce the section to lumped
// first-order elements the same way). The solar drive is weighted by the day's clearness,
// estimated from the air temperature's daily range: clouds damp both (the weather-station
// proxy of the sunshine a site without a pyranometer lacks).
#include <array>
#include <cstddef>
#include <vector>

namespace tlsmon::thermal {

// One reading of the air temperature (the epoch's meteo row).
struct AirReading {
    double t = 0;  // UTC seconds
    double temperature_c = 0;
};

struct Location {
    double latitude_deg = 0;
    double longitude_deg = 0;  // east positive
};

// The two time constants, hours (0: no lag).
struct Lags {
    double surface_h = 1.0;
    double section_h = 3.0;
};

struct DriverOptions {
    Location location;
    double max_gap_h = 2.0;        // a longer gap in the air readings breaks the lag
    double range_window_h = 24.0;  // the daily range's trailing window
    double step_s = 300.0;         // integration step of the lags
    double spin_up_h = 0.0;        // 0: the range window, at least three times the lags
};

// The drivers at one time.
struct Drivers {
    double air_c = 0;               // lagged air temperature, °C
    std::array<double, 4> solar{};  // lagged clear-sky irradiance × daily amplitude (kFaceNames)
    double daily_amplitude_c = 0;   // the air temperature's daily amplitude (not lagged)
    // The air readings cover the lags' memory (the spin-up, spin_up_seconds) before this time
    // without a gap longer than max_gap_h, the newest no older than max_gap_h; false: the drivers
    // are not known (never filled from stale air).
    bool complete = false;
    double air_age_h = 0;  // hours since the newest air reading at or before this time
};

// The spin-up the drivers need before a time to be complete, seconds: options.spin_up_h, or
// the range window and at least three times the sum of the lags (the state then holds e⁻³ of
// its start, which began in equilibrium with the drive).
double spin_up_seconds(const Lags& lags, const DriverOptions& options);

// The drive before the lags, at knots every step from the first reading and at each time asked:
// the air interpolated linearly between readings, the clear-sky irradiance on the faces
// (core/solar.hpp) weighted by the daily amplitude of the air temperature — the amplitude of
// the 24-hour harmonic fitted with a linear trend to the trailing window's readings, which
// clouds damp as they damp the sun. Built once, lagged for every pair of time constants.
struct DriveKnot {
    double t = 0;
    double air = 0;
    std::array<double, 4> solar{};
    double daily_amplitude_c = 0;
    double air_age_h = 0;  // since the newest reading at or before t
    double since_h = 0;    // since the start of the gap-free stretch of readings
};
struct DriveTrack {
    DriverOptions options;
    std::vector<DriveKnot> knots;
    std::vector<std::ptrdiff_t> at_time;  // the knot of each time asked; −1: before the readings
};
DriveTrack drive_track(const std::vector<AirReading>& air, const std::vector<double>& times,
                       const DriverOptions& options);
// The drivers at the times asked, through two first-order lags in series.
std::vector<Drivers> lagged_drivers(const DriveTrack& track, const Lags& lags);

// Both at once: the drivers at each of `times` (ascending, UTC seconds) from the readings
// (ascending).
// Between readings the air is interpolated linearly; a time after the last reading uses none
// newer than max_gap_h (older: incomplete), and a time before the readings' spin-up is
// incomplete.
std::vector<Drivers> thermal_drivers(const std::vector<AirReading>& air,
                                     const std::vector<double>& times, const Lags& lags,
                                     const DriverOptions& options);

}  // namespace tlsmon::thermal
