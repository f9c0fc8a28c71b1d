#include "algorithms/m3c2/region_index.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::m3c2 {

namespace {

// Cell coordinates relative to the origin, 21 bits each: ±2^20 cells on every axis. Regions
// must lie within ±2^19 cells, so a point beyond ±2^20 is farther than any region reaches.
constexpr std::int64_t kHalf = std::int64_t{1} << 20;
constexpr std::int64_t kRegionLimit = std::int64_t{1} << 19;
constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

std::uint64_t pack(const Eigen::Matrix<std::int64_t, 3, 1>& i) {
    return (static_cast<std::uint64_t>(i.x() + kHalf) << 42) |
           (static_cast<std::uint64_t>(i.y() + kHalf) << 21) |
           static_cast<std::uint64_t>(i.z() + kHalf);
}

// splitmix64's finaliser: neighbouring cells land far apart in the table.
Eigen::Vector3d first_finite(const std::vector<Eigen::Vector3d>& centres) {
    for (const auto& c : centres)
        if (c.allFinite()) return c;
    return Eigen::Vector3d::Zero();
}

std::uint64_t mix(std::uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

}  // namespace

std::optional<std::uint64_t> RegionIndex::key_of(const Eigen::Vector3d& p) const {
    Eigen::Matrix<std::int64_t, 3, 1> i;
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor((p[a] - origin_[a]) * inverse_cell_);
        if (!(f >= -static_cast<double>(kHalf) && f < static_cast<double>(kHalf)))
            return std::nullopt;  // also NaN
        i[a] = static_cast<std::int64_t>(f);
    }
    return pack(i);
}

std::span<const std::uint32_t> RegionIndex::regions_in(std::uint64_t key) const {
    if (table_.empty()) return {};
    for (std::uint64_t h = mix(key) & mask_;; h = (h + 1) & mask_) {
        const Slot& s = table_[h];
        if (s.key == key)
            return {regions_.data() + cell_begin_[s.cell],
                    regions_.data() + cell_begin_[s.cell + 1]};
        if (s.key == kEmpty) return {};
    }
}

// Every cell whose centre lies within the region grown by the cell's half-diagonal (plus a
// margin for rounding) is registered: a point of the region lies in such a cell, since the
// cell's points are within a half-diagonal of its centre and the tests are 1-Lipschitz.
template <class Extent, class Reaches>
void RegionIndex::build(std::size_t n, Extent&& extent, Reaches&& reaches, unsigned threads) {
    inverse_cell_ = 1.0 / cell_;
    const double half_diagonal = cell_ * std::sqrt(3.0) / 2.0;
    using Cell = Eigen::Matrix<std::int64_t, 3, 1>;

    // The cells of region k: calls emit(key) for each; returns false for no region.
    auto for_each_cell = [&](std::size_t k, auto&& emit) {
        Eigen::Vector3d centre, half_extent;
        if (!extent(k, centre, half_extent)) return;
        const double margin = 1e-9 * (1.0 + centre.cwiseAbs().maxCoeff()) + 1e-6 * cell_;
        const Eigen::Vector3d lo_f =
            ((centre - half_extent).array() - margin - origin_.array()) * inverse_cell_;
        const Eigen::Vector3d hi_f =
            ((centre + half_extent).array() + margin - origin_.array()) * inverse_cell_;
        Cell lo, hi;
        for (int a = 0; a < 3; ++a) {
            const double l = std::floor(lo_f[a]), h = std::floor(hi_f[a]);
            if (!(l >= -static_cast<double>(kRegionLimit) && h < static_cast<double>(kRegionLimit)))
                throw Error("m3c2: the core points spread over more than 2^19 cells of " +
                            std::to_string(cell_) + " m from the first one");
            lo[a] = static_cast<std::int64_t>(l);
            hi[a] = static_cast<std::int64_t>(h);
        }
        Cell i;
        for (i.x() = lo.x(); i.x() <= hi.x(); ++i.x())
            for (i.y() = lo.y(); i.y() <= hi.y(); ++i.y())
                for (i.z() = lo.z(); i.z() <= hi.z(); ++i.z()) {
                    const Eigen::Vector3d c =
                        origin_ + (i.cast<double>().array() + 0.5).matrix() * cell_;
                    if (reaches(k, c, half_diagonal + margin)) emit(pack(i));
                }
    };

    boxes_.assign(n, Eigen::AlignedBox3d());
    for (std::size_t k = 0; k < n; ++k) {
        Eigen::Vector3d centre, half_extent;
        if (extent(k, centre, half_extent))
            boxes_[k] = Eigen::AlignedBox3d(centre - half_extent, centre + half_extent);
    }
    std::vector<std::uint64_t> first(n + 1, 0);
    parallel_for(
        n,
        [&](std::size_t k) {
            std::uint64_t count = 0;
            for_each_cell(k, [&](std::uint64_t) { ++count; });
            first[k + 1] = count;
        },
        threads);
    for (std::size_t k = 0; k < n; ++k) first[k + 1] += first[k];
    std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs(first[n]);
    parallel_for(
        n,
        [&](std::size_t k) {
            std::uint64_t at = first[k];
            for_each_cell(k, [&](std::uint64_t key) {
                pairs[at++] = {key, static_cast<std::uint32_t>(k)};
            });
        },
        threads);
    std::sort(pairs.begin(), pairs.end());

    regions_.resize(pairs.size());
    cell_begin_.clear();
    std::vector<std::uint64_t> keys;
    for (std::size_t j = 0; j < pairs.size(); ++j) {
        if (j == 0 || pairs[j].first != pairs[j - 1].first) {
            keys.push_back(pairs[j].first);
            cell_begin_.push_back(j);
        }
        regions_[j] = pairs[j].second;
    }
    cell_begin_.push_back(pairs.size());
    const std::uint64_t size = std::bit_ceil(std::max<std::uint64_t>(16, 2 * keys.size()));
    mask_ = size - 1;
    table_.assign(size, Slot{kEmpty, 0});
    for (std::size_t c = 0; c < keys.size(); ++c) {
        std::uint64_t h = mix(keys[c]) & mask_;
        while (table_[h].key != kEmpty) h = (h + 1) & mask_;
        table_[h] = {keys[c], static_cast<std::uint32_t>(c)};
    }
}

RegionIndex RegionIndex::spheres(const std::vector<Eigen::Vector3d>& centres, double radius,
                                 double cell, unsigned threads) {
    RegionIndex index;
    index.cell_ = cell;
    index.origin_ = first_finite(centres);
    index.build(
        centres.size(),
        [&](std::size_t k, Eigen::Vector3d& centre, Eigen::Vector3d& half_extent) {
            centre = centres[k];
            half_extent.setConstant(radius);
            return centre.allFinite();
        },
        [&](std::size_t k, const Eigen::Vector3d& c, double slack) {
            return (c - centres[k]).norm() <= radius + slack;
        },
        threads);
    return index;
}

RegionIndex RegionIndex::cylinders(const std::vector<Eigen::Vector3d>& centres,
                                   const std::vector<Eigen::Vector3d>& axes, double radius,
                                   double half_length, double cell, unsigned threads) {
    RegionIndex index;
    index.cell_ = cell;
    index.origin_ = first_finite(centres);
    index.build(
        centres.size(),
        [&](std::size_t k, Eigen::Vector3d& centre, Eigen::Vector3d& half_extent) {
            centre = centres[k];
            const Eigen::Vector3d& n = axes[k];
            if (!centre.allFinite() || !n.allFinite()) return false;
            // The box around a cylinder: per axis a, h |n_a| + r sqrt(1 - n_a^2).
            for (int a = 0; a < 3; ++a)
                half_extent[a] = half_length * std::abs(n[a]) +
                                 radius * std::sqrt(std::max(0.0, 1.0 - n[a] * n[a]));
            return true;
        },
        [&](std::size_t k, const Eigen::Vector3d& c, double slack) {
            const Eigen::Vector3d d = c - centres[k];
            const double along = d.dot(axes[k]);
            if (std::abs(along) > half_length + slack) return false;
            return (d - along * axes[k]).norm() <= radius + slack;
        },
        threads);
    return index;
}

}  // namespace tlsmon::m3c2
