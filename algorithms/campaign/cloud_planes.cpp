#include "algorithms/campaign/cloud_planes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "algorithms/campaign/local_plane.hpp"
#include "algorithms/campaign/point_grid.hpp"
#include "algorithms/campaign/thinning.hpp"
#include "core/error.hpp"

namespace tlsmon::campaign {

void validate(const CloudPlaneParameters& p) {
    if (!(p.spacing > 0 && p.spacing <= 10))
        throw Error("cloud planes: spacing must lie in (0, 10] m");
    if (!(p.radius >= p.spacing && p.radius <= 20))
        throw Error("cloud planes: radius must lie in [spacing, 20] m");
    if (p.min_neighbours < 3) throw Error("cloud planes: min_neighbours must be at least 3");
    if (!(p.max_variation > 0 && p.max_variation <= 1.0 / 3))
        throw Error("cloud planes: max_variation must lie in (0, 1/3]");
    if (!(p.grow_distance >= p.spacing && p.grow_distance <= 20))
        throw Error("cloud planes: grow_distance must lie in [spacing, 20] m");
    if (!(p.max_angle_deg > 0 && p.max_angle_deg < 90))
        throw Error("cloud planes: max_angle_deg must lie in (0, 90)");
    if (!(p.max_offset > 0 && p.max_offset <= 10))
        throw Error("cloud planes: max_offset must lie in (0, 10] m");
    if (p.min_points < 3) throw Error("cloud planes: min_points must be at least 3");
    if (!(p.min_extent >= 0)) throw Error("cloud planes: min_extent must not be negative");
    if (p.max_planes < 1) throw Error("cloud planes: max_planes must be at least 1");
}

namespace {

constexpr std::int32_t kFree = -1;

struct Plane {
    Eigen::Vector3d normal;
    double offset;  // n·x = offset
};

// The region's plane fitted on its points, or `previous` when they lie on a line.
Plane refit(std::span<const Eigen::Vector3d> points, std::span<const std::uint32_t> members,
            const Plane& previous) {
    try {
        const registration::FittedPlane f = registration::fit_plane(points, members);
        return {f.normal, f.distance()};
    } catch (const Error&) {
        return previous;
    }
}

}  // namespace

std::vector<registration::FittedPlane> detect_cloud_planes(std::span<const Eigen::Vector3d> points,
                                                           const CloudPlaneParameters& p,
                                                           unsigned threads) {
    validate(p);
    const std::vector<Eigen::Vector3d> kept =
        kept_points(points, thin_by_voxel(points, p.spacing, {}, threads));
    const std::vector<LocalPlane> local = local_planes(kept, p.radius, p.min_neighbours, threads);
    const PointGrid grid(kept, p.grow_distance);
    const auto usable = [&](std::size_t i) {
        return local[i].defined() && local[i].variation <= p.max_variation;
    };
    std::vector<std::uint32_t> seeds;
    for (std::size_t i = 0; i < kept.size(); ++i)
        if (usable(i)) seeds.push_back(std::uint32_t(i));
    // Flattest first; ties by index, so the result is the same on every run.
    std::stable_sort(seeds.begin(), seeds.end(), [&](std::uint32_t a, std::uint32_t b) {
        return local[a].variation < local[b].variation;
    });

    const double cos_max = std::cos(p.max_angle_deg * std::numbers::pi / 180.0);
    std::vector<std::int32_t> region(kept.size(), kFree);
    std::vector<registration::FittedPlane> out;
    std::vector<std::uint32_t> members;
    std::int32_t regions = 0;
    for (const std::uint32_t seed : seeds) {
        if (region[seed] != kFree) continue;
        const std::int32_t id = regions++;
        Plane plane{local[seed].normal.cast<double>(), double(local[seed].offset)};
        members.assign(1, seed);
        region[seed] = id;
        std::size_t refit_at = 8;
        for (std::size_t k = 0; k < members.size(); ++k) {
            grid.within(kept[members[k]], p.grow_distance, [&](std::uint32_t j, double) {
                if (region[j] != kFree || !usable(j)) return;
                if (std::fabs(local[j].normal.cast<double>().dot(plane.normal)) < cos_max) return;
                if (std::fabs(plane.normal.dot(kept[j]) - plane.offset) > p.max_offset) return;
                region[j] = id;
                members.push_back(j);
            });
            if (members.size() >= refit_at) {
                plane = refit(kept, members, plane);
                refit_at = 2 * members.size();
            }
        }
        // Too small a region keeps its points: they are no plane's, and seeding again from
        // each of them would find the same few.
        if (members.size() < p.min_points) continue;
        registration::FittedPlane fitted;
        try {
            fitted = registration::fit_plane(kept, members);
        } catch (const Error&) {
            continue;
        }
        if (fitted.extent_short < p.min_extent) continue;
        out.push_back(std::move(fitted));
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.points > b.points; });
    if (out.size() > p.max_planes) out.resize(p.max_planes);
    return out;
}

}  // namespace tlsmon::campaign
