#pragma once
// Rate of change of a zone quantity over a time window, in mm/day: the least-squares slope
// of the values (metres) against acquisition time over the points in [now - window, now].
#include <optional>
#include <vector>

#include "core/utc_time.hpp"

namespace tlsmon {

struct TimedValue {
    UtcSeconds time = 0;
    double value_m = 0;
};

// slope = sum((t - t_mean)(v - v_mean)) / sum((t - t_mean)^2) [m/s], times 1000 * 86400.
// nullopt when fewer than two points of the window at distinct times.
std::optional<double> rate_mm_per_day(const std::vector<TimedValue>& points, UtcSeconds now,
                                      double window_seconds);

}  // namespace tlsmon
