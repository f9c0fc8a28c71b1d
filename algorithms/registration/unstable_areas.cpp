#include "algorithms/registration/unstable_areas.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace tlsmon::registration {

namespace {

UnstableArea summarise(const std::vector<AreaPatch>& patches, std::vector<std::uint32_t> members) {
    UnstableArea a;
    a.supervoxels = std::move(members);
    a.min_change = std::numeric_limits<double>::infinity();
    a.max_change = -a.min_change;
    a.lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    a.upper = -a.lower;
    const Eigen::Vector3d first = patches[a.supervoxels.front()].normal;
    Eigen::Vector3d normals = Eigen::Vector3d::Zero();
    for (const auto k : a.supervoxels) {
        const auto& p = patches[k];
        a.centre += p.centroid;
        a.lower = a.lower.cwiseMin(p.centroid);
        a.upper = a.upper.cwiseMax(p.centroid);
        normals += p.normal.dot(first) < 0 ? -p.normal : p.normal;
        if (!std::isnan(p.change)) {
            a.min_change = std::min(a.min_change, double(p.change));
            a.max_change = std::max(a.max_change, double(p.change));
        }
        if (!std::isnan(p.lod)) a.max_lod = std::max(a.max_lod, double(p.lod));
    }
    a.centre /= static_cast<double>(a.supervoxels.size());
    if (normals.norm() > 0) a.normal = normals.normalized();
    for (const auto k : a.supervoxels) {
        const auto& p = patches[k];
        a.extent = std::max(a.extent, (p.centroid - a.centre).norm());
        const double c = std::min(1.0, std::abs(p.normal.normalized().dot(a.normal)));
        a.normal_spread_rad = std::max(a.normal_spread_rad, std::acos(c));
    }
    return a;
}

}  // namespace

std::vector<std::uint32_t> unstable_run(const std::vector<std::uint8_t>& now,
                                        const std::vector<std::vector<std::uint8_t>>& before,
                                        int count, std::uint8_t unstable, bool first_time) {
    const auto K = static_cast<std::size_t>(std::max(count, 1));
    if (before.size() < K - 1) return {};
    for (const auto& b : before) {
        if (b.size() != now.size()) return {};
    }
    std::vector<std::uint32_t> run;
    for (std::size_t k = 0; k < now.size(); ++k) {
        bool in_run = now[k] == unstable;
        for (std::size_t j = 0; j + 1 < K && in_run; ++j) in_run = before[j][k] == unstable;
        const bool reported = first_time && before.size() >= K && before[K - 1][k] == unstable;
        if (in_run && !reported) run.push_back(static_cast<std::uint32_t>(k));
    }
    return run;
}

std::vector<UnstableArea> unstable_areas(const std::vector<AreaPatch>& patches,
                                         const std::vector<std::uint32_t>& members, double reach) {
    std::vector<std::size_t> parent(members.size());
    for (std::size_t i = 0; i < members.size(); ++i) parent[i] = i;
    const auto root = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    const double reach2 = reach * reach;
    for (std::size_t i = 0; i < members.size(); ++i) {
        for (std::size_t j = i + 1; j < members.size(); ++j) {
            if ((patches[members[i]].centroid - patches[members[j]].centroid).squaredNorm() <=
                reach2)
                parent[root(i)] = root(j);
        }
    }
    std::map<std::size_t, std::vector<std::uint32_t>> groups;
    for (std::size_t i = 0; i < members.size(); ++i) groups[root(i)].push_back(members[i]);
    std::vector<UnstableArea> out;
    for (auto& [r, group] : groups) {
        if (group.size() < kMinAreaSupervoxels) continue;
        std::sort(group.begin(), group.end());
        out.push_back(summarise(patches, std::move(group)));
    }
    std::sort(out.begin(), out.end(), [](const UnstableArea& a, const UnstableArea& b) {
        return a.supervoxels.front() < b.supervoxels.front();
    });
    return out;
}

}  // namespace tlsmon::registration
