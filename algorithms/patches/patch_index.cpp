#include "algorithms/patches/patch_index.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::patches {

std::size_t Footprint::cells() const {
    return static_cast<std::size_t>(std::count(occupied.begin(), occupied.end(), 1));
}

Footprint footprint_of(const PatchFrame& frame, std::span<const Eigen::Vector3d> samples,
                       double cell) {
    if (!(cell > 0)) throw Error("patch footprint: the cell size must be > 0");
    Footprint f;
    f.cell = cell;
    if (samples.empty()) return f;
    std::vector<std::pair<int, int>> ij;
    int i0 = INT32_MAX, j0 = INT32_MAX, i1 = INT32_MIN, j1 = INT32_MIN;
    for (const auto& p : samples) {
        const Eigen::Vector3d q = frame.local(p);
        const int i = int(std::floor(q.x() / cell)), j = int(std::floor(q.y() / cell));
        ij.emplace_back(i, j);
        i0 = std::min(i0, i), j0 = std::min(j0, j), i1 = std::max(i1, i), j1 = std::max(j1, j);
    }
    f.u0 = i0, f.v0 = j0, f.width = i1 - i0 + 1, f.height = j1 - j0 + 1;
    f.occupied.assign(std::size_t(f.width) * std::size_t(f.height), 0);
    for (const auto& [i, j] : ij)
        f.occupied[std::size_t(j - j0) * std::size_t(f.width) + std::size_t(i - i0)] = 1;
    return f;
}

std::vector<Eigen::Vector3d> cell_centres(const Patch& patch) {
    const Footprint& f = patch.footprint;
    std::vector<Eigen::Vector3d> out;
    out.reserve(f.cells());
    for (int j = 0; j < f.height; ++j)
        for (int i = 0; i < f.width; ++i)
            if (f.occupied[std::size_t(j) * std::size_t(f.width) + std::size_t(i)])
                out.push_back(patch.frame.origin + (f.u0 + i + 0.5) * f.cell * patch.frame.u +
                              (f.v0 + j + 0.5) * f.cell * patch.frame.v);
    return out;
}

PatchIndex::PatchIndex(std::vector<Patch> patches, double search_depth)
    : patches_(std::move(patches)), depth_(search_depth) {
    if (!(depth_ > 0)) throw Error("patch index: the search depth must be > 0");
    // Each patch's box: its footprint's corners ± the depth along the normal.
    std::vector<Eigen::AlignedBox3d> boxes;
    double largest = 0;
    for (const auto& p : patches_) {
        Eigen::AlignedBox3d box;
        const auto& f = p.footprint;
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int c = -1; c <= 1; c += 2) {
                    const double u = (f.u0 + a * f.width) * f.cell,
                                 v = (f.v0 + b * f.height) * f.cell;
                    box.extend(p.frame.origin + u * p.frame.u + v * p.frame.v +
                               c * depth_ * p.frame.normal);
                }
        largest = std::max(largest, box.sizes().maxCoeff());
        bounds_.extend(box);
        boxes.push_back(box);
    }
    grid_ = std::max(largest, 1e-3);
    for (const auto& p : patches_) {
        const auto& f = p.footprint;
        Eigen::Vector2d sum = Eigen::Vector2d::Zero();
        double n = 0;
        for (int j = 0; j < f.height; ++j)
            for (int i = 0; i < f.width; ++i)
                if (f.occupied[std::size_t(j) * std::size_t(f.width) + std::size_t(i)]) {
                    sum += Eigen::Vector2d(f.u0 + i + 0.5, f.v0 + j + 0.5) * f.cell;
                    n += 1;
                }
        centres_.push_back(n > 0 ? Eigen::Vector2d(sum / n) : Eigen::Vector2d::Zero());
    }
    for (std::size_t k = 0; k < boxes.size(); ++k) {
        const Eigen::Vector3d lo = (boxes[k].min() / grid_).array().floor();
        const Eigen::Vector3d hi = (boxes[k].max() / grid_).array().floor();
        for (double x = lo.x(); x <= hi.x(); ++x)
            for (double y = lo.y(); y <= hi.y(); ++y)
                for (double z = lo.z(); z <= hi.z(); ++z)
                    cells_[key(Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5) * grid_)].push_back(
                        static_cast<std::int32_t>(k));
    }
}

std::int64_t PatchIndex::key(const Eigen::Vector3d& p) const {
    // 21 bits per axis: ±1,048,576 cells, far beyond any site at a patch's size.
    const auto c = [&](double x) {
        return static_cast<std::int64_t>(std::floor(x / grid_)) & ((std::int64_t(1) << 21) - 1);
    };
    return (c(p.x()) << 42) | (c(p.y()) << 21) | c(p.z());
}

std::int32_t PatchIndex::find(const Eigen::Vector3d& p, Eigen::Vector3d& uvw) const {
    if (!bounds_.contains(p)) return -1;
    const auto it = cells_.find(key(p));
    if (it == cells_.end()) return -1;
    std::int32_t best = -1;
    for (const auto k : it->second) {
        const Patch& patch = patches_[std::size_t(k)];
        const Eigen::Vector3d q = patch.frame.local(p);
        if (std::abs(q.z()) > depth_ || !patch.footprint.covers(q.x(), q.y())) continue;
        if (best >= 0) {
            // One surface: the footprint centre nearer in the plane; else the plane nearer.
            const bool one_surface = std::abs(q.z() - uvw.z()) <= kOneSurface;
            const bool nearer =
                one_surface ? (q.head<2>() - centres_[std::size_t(k)]).squaredNorm() <
                                  (uvw.head<2>() - centres_[std::size_t(best)]).squaredNorm()
                            : std::abs(q.z()) < std::abs(uvw.z());
            if (!nearer) continue;
        }
        best = k;
        uvw = q;
    }
    return best;
}

std::vector<std::vector<PatchHit>> patch_hits(const PatchIndex& index,
                                              std::span<const Eigen::Vector3d> points,
                                              const Eigen::Matrix3d& A, const Eigen::Vector3d& t,
                                              unsigned threads, bool every,
                                              std::span<const std::uint8_t> skip) {
    constexpr std::size_t kBlock = 1 << 16;
    const std::size_t blocks = (points.size() + kBlock - 1) / kBlock;
    std::vector<std::vector<std::pair<std::int32_t, PatchHit>>> hits(blocks);
    parallel_for(
        blocks,
        [&](std::size_t b) {
            const std::size_t end = std::min(points.size(), (b + 1) * kBlock);
            for (std::size_t i = b * kBlock; i < end; ++i) {
                if (!points[i].allFinite() || (!skip.empty() && skip[i])) continue;
                const Eigen::Vector3d q = A * points[i] + t;
                if (every) {
                    index.for_each(q, [&](std::int32_t k, const Eigen::Vector3d& uvw) {
                        hits[b].push_back({k, {uvw.cast<float>(), std::uint32_t(i)}});
                    });
                    continue;
                }
                Eigen::Vector3d uvw;
                const auto k = index.find(q, uvw);
                if (k >= 0) hits[b].push_back({k, {uvw.cast<float>(), std::uint32_t(i)}});
            }
        },
        threads);
    std::vector<std::vector<PatchHit>> out(index.patches().size());
    for (const auto& block : hits)
        for (const auto& [k, h] : block) out[std::size_t(k)].push_back(h);
    return out;
}

std::vector<std::vector<Eigen::Vector3f>> patch_points(const PatchIndex& index,
                                                       std::span<const Eigen::Vector3d> points,
                                                       const Eigen::Matrix3d& A,
                                                       const Eigen::Vector3d& t, unsigned threads,
                                                       std::span<const std::uint8_t> skip) {
    const auto hits = patch_hits(index, points, A, t, threads, false, skip);
    std::vector<std::vector<Eigen::Vector3f>> out(hits.size());
    for (std::size_t k = 0; k < hits.size(); ++k) {
        out[k].reserve(hits[k].size());
        for (const auto& h : hits[k]) out[k].push_back(h.uvw);
    }
    return out;
}

}  // namespace tlsmon::patches
