#pragma once
// Everything about one epoch that does not depend on the ray: its time, the air and the
// sun, the pier's thermal bending and the atmosphere's range scale. Computed once per epoch
// (a few milliseconds: the spin-up of the thermal lags), shared by the renderer and the
// truth, and a pure function of (site, epoch, UTC time).
#include <cstdint>

#include "simulator/atmosphere.hpp"
#include "simulator/deformation.hpp"
#include "simulator/weather.hpp"

namespace tlsmon::sim {

// `tlsmon simulate --start`'s default, 2026-06-01T06:00:00Z: the series start assumed by
// the calls that give only the hours since the first epoch.
constexpr std::int64_t kDefaultStartUtc = 1780293600;

struct EpochConditions {
    int epoch = 0;
    double hours = 0.0;    // since the first epoch (drives the scanner drift)
    std::int64_t utc = 0;  // acquisition time (drives the weather)
    ThermalState thermal;
    ThermalBending bending;
    AtmosphereEffect atmosphere;
};

EpochConditions epoch_conditions(const Site& site, int epoch, double hours, std::int64_t utc);
// The same at kDefaultStartUtc + hours.
EpochConditions epoch_conditions(const Site& site, int epoch, double hours);

}  // namespace tlsmon::sim
