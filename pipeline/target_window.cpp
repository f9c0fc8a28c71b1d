#include "pipeline/target_window.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tlsmon {

namespace {

// Angle a − b wrapped to (−π, π].
double wrapped(double a, double b) {
    double d = std::remainder(a - b, 2.0 * std::numbers::pi);
    return d;
}

struct Directions {
    const Scan& scan;
    Eigen::Affine3d to_scanner;  // project -> scanner frame
    double azimuth(std::size_t i) const {
        const Eigen::Vector3d q = to_scanner * scan.xyz[i];
        return std::atan2(q.y(), q.x());
    }
    double elevation(std::size_t i) const {
        const Eigen::Vector3d q = to_scanner * scan.xyz[i];
        return std::atan2(q.z(), std::hypot(q.x(), q.y()));
    }
};

// First index in [lo, hi) for which `pred` is false, `pred` true then false along the range.
template <class Pred>
std::size_t partition_point(std::size_t lo, std::size_t hi, Pred pred) {
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (pred(mid))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

bool grid_ordered(const Scan& scan) {
    if (!scan.grid || scan.grid->column.size() != scan.size() || scan.size() < 2) return false;
    const auto& g = *scan.grid;
    // Sampled check of the column-major order; a violation found later falls back as well.
    const std::size_t n = scan.size(), step = std::max<std::size_t>(1, n / 1024);
    for (std::size_t i = step; i < n; i += step) {
        const auto a = std::uint64_t{g.column[i - step]} * g.rows + g.row[i - step];
        const auto b = std::uint64_t{g.column[i]} * g.rows + g.row[i];
        if (a > b) return false;
    }
    return true;
}

TargetWindow linear(const Scan& scan, const Eigen::Vector3d& predicted, double radius) {
    TargetWindow w;
    const double r2 = radius * radius;
    for (std::size_t i = 0; i < scan.size(); ++i) {
        if ((scan.xyz[i] - predicted).squaredNorm() <= r2) w.indices.push_back(i);
    }
    w.examined = scan.size();
    return w;
}

}  // namespace

TargetWindow points_near(const Scan& scan, const Eigen::Vector3d& predicted, double radius) {
    if (!grid_ordered(scan)) return linear(scan, predicted, radius);
    const Directions dir{scan, scan.pose.inverse()};
    const Eigen::Vector3d q = dir.to_scanner * predicted;
    const double distance = q.norm();
    if (!(distance > radius)) return linear(scan, predicted, radius);
    const double az0 = std::atan2(q.y(), q.x());
    const double el0 = std::atan2(q.z(), std::hypot(q.x(), q.y()));
    // The half-angle of the sphere of `radius` about the prediction, seen from the scanner;
    // in azimuth widened by 1/cos(elevation) (meridians converge towards the zenith).
    const double half = std::asin(radius / distance);
    const double half_az =
        std::min(std::numbers::pi, half / std::max(1e-3, std::cos(std::fabs(el0) + half)));
    const auto& g = *scan.grid;
    const std::size_t n = scan.size();
    // The azimuth runs one way along the file: its sense from the first and last column.
    const double sense = wrapped(dir.azimuth(n - 1), dir.azimuth(0)) < 0 ? -1.0 : 1.0;
    const auto along = [&](std::size_t i) { return sense * wrapped(dir.azimuth(i), az0); };
    const std::size_t begin =
        partition_point(0, n, [&](std::size_t i) { return along(i) < -half_az; });
    const std::size_t end =
        partition_point(begin, n, [&](std::size_t i) { return along(i) <= half_az; });
    TargetWindow w;
    w.through_grid = true;
    const double r2 = radius * radius;
    for (std::size_t s = begin; s < end;) {
        // One column: [s, e).
        const std::uint32_t c = g.column[s];
        const std::size_t e =
            partition_point(s, end, [&](std::size_t i) { return g.column[i] == c; });
        if (e > s + 1) {
            const double el_sense = dir.elevation(e - 1) < dir.elevation(s) ? -1.0 : 1.0;
            const auto up = [&](std::size_t i) { return el_sense * (dir.elevation(i) - el0); };
            const std::size_t a =
                partition_point(s, e, [&](std::size_t i) { return up(i) < -half; });
            const std::size_t b =
                partition_point(a, e, [&](std::size_t i) { return up(i) <= half; });
            for (std::size_t i = a; i < b; ++i) {
                ++w.examined;
                if ((scan.xyz[i] - predicted).squaredNorm() <= r2) w.indices.push_back(i);
            }
        } else if ((scan.xyz[s] - predicted).squaredNorm() <= r2) {
            w.indices.push_back(s);
        }
        s = e;
    }
    return w;
}

}  // namespace tlsmon
