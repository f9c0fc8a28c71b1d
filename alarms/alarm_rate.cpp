#include "alarms/alarm_rate.hpp"

namespace tlsmon {

std::optional<double> rate_per_day(const std::vector<TimedValue>& points, UtcSeconds now,
                                   double window_seconds) {
    double n = 0, t_sum = 0, v_sum = 0;
    auto inside = [&](const TimedValue& p) {
        return p.time <= now && static_cast<double>(now - p.time) <= window_seconds;
    };
    for (const auto& p : points) {
        if (!inside(p)) continue;
        n += 1;
        t_sum += static_cast<double>(p.time - now);  // relative: keeps the sums well conditioned
        v_sum += p.value;
    }
    if (n < 2) return std::nullopt;
    const double t_mean = t_sum / n, v_mean = v_sum / n;
    double stt = 0, stv = 0;
    for (const auto& p : points) {
        if (!inside(p)) continue;
        const double dt = static_cast<double>(p.time - now) - t_mean;
        stt += dt * dt;
        stv += dt * (p.value - v_mean);
    }
    if (stt <= 0) return std::nullopt;
    return stv / stt * 86400.0;
}

std::optional<double> rate_mm_per_day(const std::vector<TimedValue>& points, UtcSeconds now,
                                      double window_seconds) {
    const auto rate = rate_per_day(points, now, window_seconds);
    if (!rate) return std::nullopt;
    return *rate * 1000.0;
}

}  // namespace tlsmon
