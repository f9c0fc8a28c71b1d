#include "algorithms/thermal/thermal_drivers.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>

#include "core/solar.hpp"

namespace tlsmon::thermal {

namespace {

constexpr double kHour = 3600.0;

// The day's clearness as the air temperature's daily amplitude: the amplitude of the 24-hour
// harmonic fitted, with a linear trend (the day-to-day change of the mean), to the readings of
// the trailing window: T(t) = a + b·t + c·cos ωt + d·sin ωt, amplitude √(c² + d²).
class DailyAmplitude {
  public:
    explicit DailyAmplitude(double window_s) : window_(window_s) {}
    void add(const AirReading& r) {
        readings_.push_back(r);
        dirty_ = true;
    }
    double at(double t) {
        while (!readings_.empty() && readings_.front().t < t - window_) {
            readings_.pop_front();
            dirty_ = true;
        }
        if (dirty_) {
            amplitude_ = fit(t);
            dirty_ = false;
        }
        return amplitude_;
    }

  private:
    double fit(double t) const {
        if (readings_.size() < 8) return 0.0;
        constexpr double omega = 2.0 * std::numbers::pi / 86400.0;
        Eigen::Matrix4d n = Eigen::Matrix4d::Zero();
        Eigen::Vector4d b = Eigen::Vector4d::Zero();
        for (const AirReading& r : readings_) {
            const Eigen::Vector4d x((1.0), (r.t - t) / window_, std::cos(omega * r.t),
                                    std::sin(omega * r.t));
            n += x * x.transpose();
            b += x * r.temperature_c;
        }
        const Eigen::LDLT<Eigen::Matrix4d> ldlt(n);
        if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return 0.0;
        const Eigen::Vector4d c = ldlt.solve(b);
        return std::hypot(c(2), c(3));
    }

    double window_;
    std::deque<AirReading> readings_;
    double amplitude_ = 0.0;
    bool dirty_ = false;
};

}  // namespace

double spin_up_seconds(const Lags& lags, const DriverOptions& options) {
    if (options.spin_up_h > 0.0) return options.spin_up_h * kHour;
    return std::max(options.range_window_h, 3.0 * (lags.surface_h + lags.section_h)) * kHour;
}

DriveTrack drive_track(const std::vector<AirReading>& air, const std::vector<double>& times,
                       const DriverOptions& options) {
    DriveTrack track;
    track.options = options;
    track.at_time.assign(times.size(), -1);
    if (air.empty() || times.empty()) return track;
    const double max_gap = options.max_gap_h * kHour;
    const Location& where = options.location;
    std::size_t next = 0;  // first reading after the current knot
    DailyAmplitude amplitude(options.range_window_h * kHour);
    double segment_start = air.front().t;  // start of the current gap-free stretch of readings
    const auto knot = [&](double t) {
        while (next < air.size() && air[next].t <= t) {
            if (next > 0 && air[next].t - air[next - 1].t > max_gap) segment_start = air[next].t;
            amplitude.add(air[next]);
            ++next;
        }
        DriveKnot k;
        k.t = t;
        // The air between readings linearly, held past the ends.
        if (next == 0) {
            k.air = air.front().temperature_c;
        } else if (next == air.size()) {
            k.air = air.back().temperature_c;
        } else {
            const AirReading& a = air[next - 1];
            const AirReading& b = air[next];
            k.air = a.temperature_c +
                    (b.temperature_c - a.temperature_c) * (t - a.t) / std::max(b.t - a.t, 1.0);
        }
        k.daily_amplitude_c = amplitude.at(t);
        const auto irradiance =
            clear_sky_face_irradiance(sun_position(where.latitude_deg, where.longitude_deg, t));
        for (int f = 0; f < 4; ++f) k.solar[f] = k.daily_amplitude_c * irradiance[f];
        k.air_age_h =
            next == 0 ? std::numeric_limits<double>::infinity() : (t - air[next - 1].t) / kHour;
        k.since_h = (t - segment_start) / kHour;
        track.knots.push_back(k);
    };
    // Knots every step from the first reading, and at each time asked.
    double t = air.front().t;
    knot(t);
    for (std::size_t i = 0; i < times.size(); ++i) {
        if (times[i] < t) continue;  // before the readings: no drivers
        while (t + options.step_s < times[i]) {
            t += options.step_s;
            knot(t);
        }
        if (times[i] > t) {
            t = times[i];
            knot(t);
        }
        track.at_time[i] = static_cast<std::ptrdiff_t>(track.knots.size()) - 1;
    }
    return track;
}

std::vector<Drivers> lagged_drivers(const DriveTrack& track, const Lags& lags) {
    std::vector<Drivers> out(track.at_time.size());
    if (track.knots.empty()) return out;
    const double spin_up = spin_up_seconds(lags, track.options) / kHour;
    const double tau_s = lags.surface_h * kHour, tau = lags.section_h * kHour;
    // From the first knot, in equilibrium with its drive.
    std::vector<Drivers> at_knot(track.knots.size());
    const DriveKnot& k0 = track.knots.front();
    std::array<double, 5> x{k0.air, k0.solar[0], k0.solar[1], k0.solar[2], k0.solar[3]};
    std::array<double, 5> surface = x, section = x;
    for (std::size_t j = 0; j < track.knots.size(); ++j) {
        const DriveKnot& k = track.knots[j];
        if (j > 0) {
            const double h = k.t - track.knots[j - 1].t;
            const std::array<double, 5> x1{k.air, k.solar[0], k.solar[1], k.solar[2], k.solar[3]};
            for (int v = 0; v < 5; ++v) {
                const double s1 = lag_step(surface[v], x[v], x1[v], h, tau_s);
                section[v] = lag_step(section[v], surface[v], s1, h, tau);
                surface[v] = s1;
            }
            x = x1;
        }
        Drivers& d = at_knot[j];
        d.air_c = section[0];
        for (int f = 0; f < 4; ++f) d.solar[f] = section[1 + f];
        d.daily_amplitude_c = k.daily_amplitude_c;
        d.air_age_h = k.air_age_h;
        d.complete = k.air_age_h <= track.options.max_gap_h && k.since_h >= spin_up;
    }
    for (std::size_t i = 0; i < out.size(); ++i)
        if (track.at_time[i] >= 0) out[i] = at_knot[static_cast<std::size_t>(track.at_time[i])];
    return out;
}

std::vector<Drivers> thermal_drivers(const std::vector<AirReading>& air,
                                     const std::vector<double>& times, const Lags& lags,
                                     const DriverOptions& options) {
    return lagged_drivers(drive_track(air, times, options), lags);
}

}  // namespace tlsmon::thermal
