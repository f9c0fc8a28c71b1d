#include "algorithms/campaign/thinning.hpp"

#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <utility>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

VoxelThinning thin_by_voxel(std::span<const Eigen::Vector3d> points, double voxel,
                            std::span<const std::uint8_t> take, unsigned threads) {
    if (!(voxel >= 0 && voxel <= 100)) throw Error("campaign: thinning must lie in [0, 100] m");
    if (!take.empty() && take.size() != points.size())
        throw Error("campaign: thinning needs one flag per point");
    VoxelThinning out;
    out.voxel = voxel;
    out.of.assign(points.size(), VoxelThinning::kNone);
    const auto taken = [&](std::size_t i) {
        return points[i].allFinite() && (take.empty() || take[i] != 0);
    };
    if (voxel == 0) {
        for (std::size_t i = 0; i < points.size(); ++i)
            if (taken(i)) {
                out.of[i] = std::uint32_t(out.kept.size());
                out.kept.push_back(i);
            }
        return out;
    }
    // Each taken point keyed by its voxel (packed into 21 bits per axis, as PointGrid's: ±2^20
    // voxels), sorted: a voxel's points are then contiguous, its first point leading.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
    parallel_for(
        points.size(),
        [&](std::size_t i) {
            if (!taken(i)) {
                keyed[i] = {~std::uint64_t(0), std::uint32_t(i)};
                return;
            }
            constexpr long kOffset = 1L << 20;
            const Eigen::Vector3d q = points[i] / voxel;
            std::uint64_t k = 0;
            for (int a = 0; a < 3; ++a)
                k |= (std::uint64_t(long(std::floor(q(a))) + kOffset) & 0x1FFFFF) << (21 * a);
            keyed[i] = {k, std::uint32_t(i)};
        },
        threads);
    tbb::task_arena(threads == 0 ? tbb::task_arena::automatic : int(threads)).execute([&] {
        tbb::parallel_sort(keyed.begin(), keyed.end());
    });
    for (std::size_t k = 0; k < keyed.size() && keyed[k].first != ~std::uint64_t(0);) {
        const auto v = std::uint32_t(out.kept.size());
        out.kept.push_back(keyed[k].second);
        const std::uint64_t key = keyed[k].first;
        for (; k < keyed.size() && keyed[k].first == key; ++k) out.of[keyed[k].second] = v;
    }
    return out;
}

std::vector<Eigen::Vector3d> kept_points(std::span<const Eigen::Vector3d> points,
                                         const VoxelThinning& thinning) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(thinning.kept.size());
    for (const auto i : thinning.kept) out.push_back(points[i]);
    return out;
}

}  // namespace tlsmon::campaign
