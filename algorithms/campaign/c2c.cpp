#include "algorithms/campaign/c2c.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel_for.hpp"
#include "core/statistics.hpp"

namespace tlsmon::campaign {

std::vector<Eigen::Vector3f> c2c_vectors(const ReferenceSurface& reference,
                                         std::span<const Eigen::Vector3d> points, C2cModel model,
                                         unsigned threads) {
    std::vector<Eigen::Vector3f> out(
        points.size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
    parallel_for(
        points.size(),
        [&](std::size_t i) {
            if (!points[i].allFinite()) return;
            const std::int64_t q = reference.nearest(points[i]);
            if (q < 0) return;
            if (model == C2cModel::nearest_point || !reference.planar(q)) {
                out[i] = (reference.point(q) - points[i]).cast<float>();
                return;
            }
            const LocalPlane& plane = reference.plane(q);
            // The foot of the perpendicular: −d·n.
            out[i] = (-plane.distance(points[i]) * plane.normal.cast<double>()).cast<float>();
        },
        threads);
    return out;
}

C2cStatistics summarise(std::span<const Eigen::Vector3f> vectors) {
    C2cStatistics s;
    std::vector<double> d;
    d.reserve(vectors.size());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& v : vectors) {
        if (!v.allFinite()) {
            ++s.missing;
            continue;
        }
        d.push_back(v.cast<double>().norm());
        sum += v.cast<double>();
    }
    s.points = d.size();
    if (d.empty()) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        s.mean = s.sigma = s.rms = s.median = s.p95 = s.max = nan;
        s.mean_vector.setConstant(nan);
        return s;
    }
    const double n = double(d.size());
    double sum_d = 0, sum_dd = 0;
    for (const double x : d) {
        sum_d += x;
        sum_dd += x * x;
    }
    s.mean = sum_d / n;
    s.rms = std::sqrt(sum_dd / n);
    s.sigma = d.size() > 1 ? std::sqrt(std::max(0.0, (sum_dd - n * s.mean * s.mean) / (n - 1))) : 0;
    s.mean_vector = sum / n;
    std::sort(d.begin(), d.end());
    s.median = quantile_of_sorted(d, 0.5);
    s.p95 = quantile_of_sorted(d, 0.95);
    s.max = d.back();
    return s;
}

}  // namespace tlsmon::campaign
