#include "simulator/epoch_conditions.hpp"

#include <cmath>

namespace tlsmon::sim {

EpochConditions epoch_conditions(const Site& site, int epoch, double hours, std::int64_t utc) {
    EpochConditions c;
    c.epoch = epoch;
    c.hours = hours;
    c.utc = utc;
    c.thermal = thermal_state(site, static_cast<double>(utc));
    c.bending = thermal_bending(site, c.thermal);
    // A changed bending stiffness or restraint scales the curvature from its event on.
    const Events& e = site.events;
    if (e.bending_change_epoch >= 0 && epoch >= e.bending_change_epoch) {
        c.bending.curvature *= e.bending_factor;
        c.bending.top.head<2>() *= e.bending_factor;
    }
    c.atmosphere = atmosphere_effect(site.atmosphere, c.thermal.air);
    return c;
}

EpochConditions epoch_conditions(const Site& site, int epoch, double hours) {
    return epoch_conditions(
        site, epoch, hours,
        kDefaultStartUtc + static_cast<std::int64_t>(std::llround(hours * 3600.0)));
}

}  // namespace tlsmon::sim
