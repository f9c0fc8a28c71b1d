#include "algorithms/campaign/cut_bias.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "algorithms/campaign/point_grid.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

std::vector<double> cut_fractions(std::span<const Eigen::Vector3d> points,
                                  std::span<const std::int32_t> label, std::size_t labels,
                                  double distance, std::size_t samples, unsigned threads) {
    if (label.size() != points.size()) throw Error("campaign: one label per point is needed");
    if (!(distance > 0)) throw Error("campaign: the cut distance must be positive");
    std::vector<std::vector<std::size_t>> members(labels);
    for (std::size_t i = 0; i < points.size(); ++i)
        if (label[i] >= 0 && std::size_t(label[i]) < labels && points[i].allFinite())
            members[std::size_t(label[i])].push_back(i);
    // The probes: every k-th point of each label.
    std::vector<std::size_t> probe;
    std::vector<std::size_t> first(labels + 1, 0);
    for (std::size_t s = 0; s < labels; ++s) {
        first[s] = probe.size();
        const std::size_t k = std::max<std::size_t>(
            1, (members[s].size() + samples - 1) / std::max<std::size_t>(samples, 1));
        for (std::size_t j = 0; j < members[s].size(); j += k) probe.push_back(members[s][j]);
    }
    first[labels] = probe.size();
    const PointGrid grid(points, distance);
    std::vector<std::uint8_t> near_cut(probe.size(), 0);
    parallel_for(
        probe.size(),
        [&](std::size_t j) {
            const std::size_t i = probe[j];
            bool other = false;
            grid.within(points[i], distance,
                        [&](std::uint32_t k, double) { other = other || label[k] != label[i]; });
            near_cut[j] = other;
        },
        threads);
    std::vector<double> out(labels, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t s = 0; s < labels; ++s) {
        const std::size_t n = first[s + 1] - first[s];
        if (n == 0) continue;
        std::size_t cut = 0;
        for (std::size_t j = first[s]; j < first[s + 1]; ++j) cut += near_cut[j];
        out[s] = double(cut) / double(n);
    }
    return out;
}

double cut_bias_bound(double fraction, double distance, double range_sigma, double normal_sigma) {
    if (!(fraction > 0) || !(distance > 0) || !(range_sigma > 0)) return 0;
    const double sn = std::clamp(normal_sigma, 0.0, range_sigma);
    return fraction / distance * sn * std::sqrt(range_sigma * range_sigma - sn * sn);
}

}  // namespace tlsmon::campaign
