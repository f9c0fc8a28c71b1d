#include "algorithms/m3c2/cylinder.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "algorithms/m3c2/members.hpp"
#include "core/statistics.hpp"

namespace tlsmon::m3c2 {

namespace {

// Cells of about the cylinder's radius, longer for long thin cylinders: a few cells per
// cylinder, a few cylinders per cell.
double cell_for(const CylinderParameters& p) {
    return std::max(p.radius, p.max_depth / 4.0);
}

// The statistic as published, of all the projections given.
CylinderSide published_statistic(std::vector<double>& projections, CylinderStatistic statistic) {
    CylinderSide side;
    side.count = static_cast<std::uint32_t>(projections.size());
    if (projections.empty()) return side;
    const double n = static_cast<double>(projections.size());
    if (statistic == CylinderStatistic::mean) {
        double sum = 0.0;
        for (double v : projections) sum += v;
        side.centre = sum / n;
        if (projections.size() >= 2) {
            double squares = 0.0;
            for (double v : projections) squares += (v - side.centre) * (v - side.centre);
            side.spread = std::sqrt(squares / (n - 1.0));
        }
    } else {
        std::sort(projections.begin(), projections.end());
        side.centre = quantile_of_sorted(projections, 0.5);
        if (projections.size() >= 2)
            side.spread =
                quantile_of_sorted(projections, 0.75) - quantile_of_sorted(projections, 0.25);
    }
    side.roughness = side.spread;
    return side;
}

}  // namespace

CylinderSide statistic_of(std::vector<double>& projections, CylinderStatistic statistic,
                          double stray_distance) {
    const CylinderSide all = published_statistic(projections, statistic);
    if (statistic != CylinderStatistic::mean || !std::isfinite(stray_distance) ||
        projections.empty())
        return all;
    const auto [centre, mad] = median_and_mad(projections);
    const double limit = std::max(stray_distance, kStrayRobustSigmas * kMadToSigma * mad);
    std::erase_if(projections, [&](double v) { return !(std::abs(v - centre) <= limit); });
    const std::size_t strays = all.count - projections.size();
    if (strays == 0) return all;
    CylinderSide kept;
    if (double(strays) > kMaxStrayShare * double(all.count))
        kept.count = static_cast<std::uint32_t>(projections.size());  // two surfaces: no centre
    else
        kept = published_statistic(projections, statistic);
    kept.roughness = all.roughness;
    return kept;
}

void set_lateral(CylinderSide& side, const std::vector<Eigen::Vector3d>& cloud,
                 std::span<const std::uint32_t> members, const Eigen::Vector3d& c,
                 const Eigen::Vector3d& n) {
    if (members.empty()) return;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double squares = 0.0;
    for (std::uint32_t i : members) {
        const Eigen::Vector3d d = cloud[i] - c;
        const Eigen::Vector3d across = d - d.dot(n) * n;
        sum += across;
        squares += across.squaredNorm();
    }
    const double m = double(members.size());
    side.lateral = sum / m;
    side.lateral_spread = std::sqrt(squares / m);
}

Cylinders make_cylinders(std::vector<Eigen::Vector3d> centres, std::vector<Eigen::Vector3d> axes,
                         const CylinderParameters& parameters, unsigned threads) {
    validate(parameters);
    Cylinders cylinders;
    cylinders.index = RegionIndex::cylinders(centres, axes, parameters.radius, parameters.max_depth,
                                             cell_for(parameters), threads);
    cylinders.centres = std::move(centres);
    cylinders.axes = std::move(axes);
    cylinders.parameters = parameters;
    return cylinders;
}

std::vector<CylinderSide> cylinder_sides(const Cylinders& cylinders,
                                         const std::vector<Eigen::Vector3d>& cloud,
                                         unsigned threads, std::span<const std::uint8_t> left_out) {
    const auto& centres = cylinders.centres;
    const auto& axes = cylinders.axes;
    const CylinderParameters& p = cylinders.parameters;
    std::vector<CylinderSide> sides(centres.size());
    for_each_core_with_members(
        cloud, cylinders.index, centres.size(),
        [&](std::uint32_t k, const Eigen::Vector3d& point) {
            return in_cylinder(point, centres[k], axes[k], p.radius, p.max_depth);
        },
        [&](std::size_t k, std::span<const std::uint32_t> members) {
            std::vector<double> projections;
            projections.reserve(members.size());
            for (std::uint32_t i : members)
                projections.push_back((cloud[i] - centres[k]).dot(axes[k]));
            sides[k] = statistic_of(projections, p.statistic, p.stray_distance);
            set_lateral(sides[k], cloud, members, centres[k], axes[k]);
        },
        threads, kMemberBudget, /*single_pass=*/true, left_out);
    return sides;
}

}  // namespace tlsmon::m3c2
