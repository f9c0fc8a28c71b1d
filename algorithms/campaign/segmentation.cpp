#include "algorithms/campaign/segmentation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "algorithms/campaign/point_grid.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

namespace {

// Union–find with path halving and union by size.
class DisjointSets {
  public:
    explicit DisjointSets(std::size_t n) : parent_(n), size_(n, 1) {
        std::iota(parent_.begin(), parent_.end(), std::uint32_t(0));
    }
    std::uint32_t find(std::uint32_t i) {
        while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
        return i;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a == b) return;
        if (size_[a] < size_[b]) std::swap(a, b);
        parent_[b] = a;
        size_[a] += size_[b];
    }

  private:
    std::vector<std::uint32_t> parent_, size_;
};

VerticalityClass joined(VerticalityClass c) {
    return c == VerticalityClass::undefined ? VerticalityClass::other : c;
}

}  // namespace

void validate(const SegmentationParameters& p) {
    if (!(p.distance_factor >= 1 && p.distance_factor <= 100))
        throw Error("campaign: distance_factor must lie in [1, 100]");
    if (p.min_points < 1) throw Error("campaign: min_points must be at least 1");
    if (p.spacing_samples < 10) throw Error("campaign: spacing_samples must be at least 10");
}

double mean_spacing(std::span<const Eigen::Vector3d> points, int samples) {
    std::vector<std::size_t> finite;
    for (std::size_t i = 0; i < points.size(); ++i)
        if (points[i].allFinite()) finite.push_back(i);
    if (finite.size() < 2) return 0;
    // The cell from the area per point of the bounding box's largest face (a scanned cloud is
    // a surface): about the spacing, so a search of one cell mostly finds the neighbour.
    Eigen::AlignedBox3d box;
    for (const auto i : finite) box.extend(points[i]);
    Eigen::Vector3d size = box.sizes();
    std::sort(size.data(), size.data() + 3);
    const double cell = std::max(std::sqrt(size(1) * size(2) / double(finite.size())),
                                 1e-6 * std::max(size(2), 1.0));
    const PointGrid grid(points, cell);
    const std::size_t step = std::max<std::size_t>(1, finite.size() / std::size_t(samples));
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t k = 0; k < finite.size(); k += step) {
        const std::size_t i = finite[k];
        double best = std::numeric_limits<double>::infinity();
        for (double r = cell; !std::isfinite(best) && r < 1e3 * cell; r *= 2)
            grid.within(points[i], r, [&](std::uint32_t j, double d2) {
                if (j != i) best = std::min(best, d2);
            });
        if (std::isfinite(best)) sum += std::sqrt(best), ++n;
    }
    return n ? sum / double(n) : 0.0;
}

Segmentation segment_cloud(std::span<const Eigen::Vector3d> points,
                           std::span<const VerticalityClass> classes,
                           const SegmentationParameters& p, unsigned threads) {
    validate(p);
    if (classes.size() != points.size())
        throw Error("campaign: one verticality class per point is needed");
    Segmentation out;
    out.spacing = mean_spacing(points, p.spacing_samples);
    out.cluster.assign(points.size(), -1);
    out.segment.assign(points.size(), -1);
    if (out.spacing <= 0) return out;
    out.distance = p.distance_factor * out.spacing;
    const PointGrid grid(points, out.distance);
    DisjointSets objects(points.size()), parts(points.size());
    // The neighbour searches in parallel, a block of points at a time; the unions, which are
    // cheap, in order.
    constexpr std::size_t kBlock = 1 << 16;
    std::vector<std::vector<std::uint32_t>> neighbours(kBlock);
    for (std::size_t b = 0; b < points.size(); b += kBlock) {
        const std::size_t e = std::min(points.size(), b + kBlock);
        parallel_for(
            e - b,
            [&](std::size_t k) {
                const std::size_t i = b + k;
                auto& list = neighbours[k];
                list.clear();
                if (!points[i].allFinite()) return;
                grid.within(points[i], out.distance, [&](std::uint32_t j, double) {
                    if (j > i) list.push_back(j);  // each pair once
                });
            },
            threads);
        for (std::size_t k = 0; k < e - b; ++k) {
            const auto i = std::uint32_t(b + k);
            for (const std::uint32_t j : neighbours[k]) {
                objects.unite(i, j);
                if (joined(classes[i]) == joined(classes[j])) parts.unite(i, j);
            }
        }
    }
    // Number the clusters, then the parts of at least min_points, largest first.
    std::vector<std::int32_t> cluster_of_root(points.size(), -1);
    std::vector<std::size_t> part_size(points.size(), 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) continue;
        auto& c = cluster_of_root[objects.find(std::uint32_t(i))];
        if (c < 0) c = std::int32_t(out.clusters++);
        out.cluster[i] = c;
        ++part_size[parts.find(std::uint32_t(i))];
    }
    std::vector<std::uint32_t> roots;
    for (std::size_t r = 0; r < points.size(); ++r)
        if (part_size[r] >= std::size_t(p.min_points)) roots.push_back(std::uint32_t(r));
    std::stable_sort(roots.begin(), roots.end(),
                     [&](auto a, auto b) { return part_size[a] > part_size[b]; });
    std::vector<std::int32_t> segment_of_root(points.size(), -1);
    for (const auto r : roots) {
        segment_of_root[r] = std::int32_t(out.segments.size());
        out.segments.push_back({joined(classes[r]), out.cluster[r], part_size[r], part_size[r]});
    }
    for (std::size_t i = 0; i < points.size(); ++i)
        if (points[i].allFinite()) out.segment[i] = segment_of_root[parts.find(std::uint32_t(i))];
    return out;
}

}  // namespace tlsmon::campaign
