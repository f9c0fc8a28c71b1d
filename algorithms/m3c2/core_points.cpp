#include "algorithms/m3c2/core_points.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::m3c2 {

namespace {

using Cube = std::array<std::int64_t, 3>;

struct CubeHash {
    std::size_t operator()(const Cube& c) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (auto v : c) {
            h ^= static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
            h *= 0xbf58476d1ce4e5b9ULL;
        }
        return static_cast<std::size_t>(h ^ (h >> 31));
    }
};

struct Best {
    std::size_t index;
    double distance2;  // to the cube's centre
};

// The rule is independent of the order of comparison: nearer first, then lower index.
bool better(const Best& a, const Best& b) {
    return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
}

}  // namespace

std::vector<Eigen::Vector3d> subsample(const std::vector<Eigen::Vector3d>& cloud, double spacing,
                                       unsigned threads) {
    if (!(std::isfinite(spacing) && spacing > 0.0))
        throw Error("m3c2: core_spacing must be a positive length in metres, not " +
                    std::to_string(spacing));
    // A few parts (not one per thread) bound the memory of the partial maps.
    const std::size_t parts = std::min<std::size_t>(16, std::max<std::size_t>(1, cloud.size()));
    std::vector<std::unordered_map<Cube, Best, CubeHash>> partial(parts);
    parallel_for(
        parts,
        [&](std::size_t part) {
            auto& best = partial[part];
            const std::size_t begin = cloud.size() * part / parts;
            const std::size_t end = cloud.size() * (part + 1) / parts;
            for (std::size_t i = begin; i < end; ++i) {
                const Eigen::Vector3d& p = cloud[i];
                if (!p.allFinite()) continue;
                const Eigen::Vector3d f = (p / spacing).array().floor();
                if ((f.array().abs() > 9e15).any())
                    throw Error("m3c2: core_spacing " + std::to_string(spacing) +
                                " m is too small for coordinates of " + std::to_string(p.norm()) +
                                " m");
                const Cube cube{static_cast<std::int64_t>(f.x()), static_cast<std::int64_t>(f.y()),
                                static_cast<std::int64_t>(f.z())};
                const Eigen::Vector3d centre = (f.array() + 0.5) * spacing;
                const Best candidate{i, (p - centre).squaredNorm()};
                auto [it, inserted] = best.try_emplace(cube, candidate);
                if (!inserted && better(candidate, it->second)) it->second = candidate;
            }
        },
        threads);
    for (std::size_t part = 1; part < parts; ++part) {
        for (const auto& [cube, candidate] : partial[part]) {
            auto [it, inserted] = partial[0].try_emplace(cube, candidate);
            if (!inserted && better(candidate, it->second)) it->second = candidate;
        }
        partial[part] = {};
    }
    std::vector<Best> candidates;
    candidates.reserve(partial.empty() ? 0 : partial[0].size());
    if (!partial.empty())
        for (const auto& [cube, best] : partial[0]) candidates.push_back(best);
    std::sort(candidates.begin(), candidates.end(), better);
    // Thinning: a candidate within S/2 of a kept one is dropped. Kept points on a lattice of
    // cubes of edge S: the neighbours to check lie in the 27 cubes around.
    const double min_distance2 = 0.25 * spacing * spacing;
    std::unordered_map<Cube, std::vector<std::size_t>, CubeHash> kept;
    std::vector<std::size_t> chosen;
    for (const Best& c : candidates) {
        const Eigen::Vector3d& p = cloud[c.index];
        const Eigen::Vector3d f = (p / spacing).array().floor();
        const Cube cube{static_cast<std::int64_t>(f.x()), static_cast<std::int64_t>(f.y()),
                        static_cast<std::int64_t>(f.z())};
        bool near = false;
        for (std::int64_t dx = -1; dx <= 1 && !near; ++dx)
            for (std::int64_t dy = -1; dy <= 1 && !near; ++dy)
                for (std::int64_t dz = -1; dz <= 1 && !near; ++dz) {
                    const auto it = kept.find({cube[0] + dx, cube[1] + dy, cube[2] + dz});
                    if (it == kept.end()) continue;
                    for (std::size_t j : it->second)
                        if ((cloud[j] - p).squaredNorm() < min_distance2) near = true;
                }
        if (near) continue;
        kept[cube].push_back(c.index);
        chosen.push_back(c.index);
    }
    std::sort(chosen.begin(), chosen.end());
    std::vector<Eigen::Vector3d> core_points;
    core_points.reserve(chosen.size());
    for (std::size_t i : chosen) core_points.push_back(cloud[i]);
    return core_points;
}

}  // namespace tlsmon::m3c2
