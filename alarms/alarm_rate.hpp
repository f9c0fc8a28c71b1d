#pragma once
// Rate of change of a zone quantity over a time window: the least-squares slope of the
// values against acquisition time over the points in [now − window, now]. One function for
// the alarm rules (in mm/day) and the Modbus `.rate` registers (in the quantity's unit per
// day), so SCADA shows the rate an alarm fired on.
#include <optional>
#include <vector>

#include "core/utc_time.hpp"

namespace tlsmon {

struct TimedValue {
    UtcSeconds time = 0;
    double value = 0;
};

// slope = Σ(t − t̄)(v − v̄) / Σ(t − t̄)² [unit/s] × 86400: the value's unit per day. nullopt
// when the window holds fewer than two points at distinct times.
std::optional<double> rate_per_day(const std::vector<TimedValue>& points, UtcSeconds now,
                                   double window_seconds);

// The rate an alarm rule evaluates, of a quantity in metres: mm/day.
std::optional<double> rate_mm_per_day(const std::vector<TimedValue>& points, UtcSeconds now,
                                      double window_seconds);

// The window of the Modbus `.rate` registers of a zone quantity no rate rule watches.
inline constexpr double kDefaultRateWindowSeconds = 86400.0;

}  // namespace tlsmon
