#pragma once
// The points of a cloud inside each core point's region, found by streaming the cloud once
// through a RegionIndex (region_index.hpp). Each core point's members come in the cloud's
// order whatever the number of threads, so results built from them do not depend on it.
// When the members of all core points would not fit in `budget` entries, the core points are
// taken in consecutive batches, each with its own pass over the cloud. `left_out`: empty, or one
// entry per point of the cloud, non-zero for a point that is no one's member (an edge point:
// pipeline/m3c2_stage.hpp), so a caller leaves points out without copying the rest.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "algorithms/m3c2/region_index.hpp"
#include "core/error.hpp"
#include "core/parallel_for.hpp"

namespace tlsmon::m3c2 {

inline constexpr std::size_t kMemberBudget = std::size_t{1} << 23;

// contains(k, p): whether point p lies in the region of core point k (the exact test).
// visit(k, members): called once for every core point k in [0, cores), in parallel, with the
// indices of its member points in ascending order.
// (core, point) pairs found in one chunk of the cloud, in blocks that are kept for the next
// batch: no reallocation, no copying as they grow.
class FoundPairs {
  public:
    void add(std::uint32_t core, std::uint32_t point) {
        if (used_ == kBlock) {
            ++block_;
            used_ = 0;
        }
        // Left uninitialised: every entry is written before it is read.
        if (block_ == blocks_.size()) blocks_.emplace_back(new Found[kBlock]);
        blocks_[block_][used_++] = {core, point};
    }
    std::size_t size() const { return blocks_.empty() ? 0 : block_ * kBlock + used_; }
    template <class F>
    void for_each(F&& f) const {
        for (std::size_t b = 0; b < blocks_.size() && b <= block_; ++b) {
            const std::size_t n = b == block_ ? used_ : kBlock;
            for (std::size_t j = 0; j < n; ++j) f(blocks_[b][j].core, blocks_[b][j].point);
        }
    }
    void clear() { block_ = used_ = 0; }
    void release() {
        blocks_.clear();
        clear();
    }

  private:
    static constexpr std::size_t kBlock = std::size_t{1} << 14;
    struct Found {
        std::uint32_t core, point;
    };
    std::vector<std::unique_ptr<Found[]>> blocks_;
    std::size_t block_ = 0, used_ = 0;
};

// `single_pass`: first try to find every member in one pass (worth it when they are likely
// to fit the budget, as cylinders' do).
template <class Contains, class Visit>
void for_each_core_with_members(const std::vector<Eigen::Vector3d>& cloud, const RegionIndex& index,
                                std::size_t cores, Contains&& contains, Visit&& visit,
                                unsigned threads = 0, std::size_t budget = kMemberBudget,
                                bool single_pass = true,
                                std::span<const std::uint8_t> left_out = {}) {
    if (cloud.size() > std::size_t{0xFFFFFFFF})
        throw Error("m3c2: a cloud of more than 2^32 - 1 points");
    if (!left_out.empty() && left_out.size() != cloud.size())
        throw Error("m3c2: the points left out do not match the cloud");
    const auto kept = [&](std::size_t i) { return left_out.empty() || !left_out[i]; };
    constexpr std::size_t kChunk = std::size_t{1} << 16;
    const std::size_t chunks = (cloud.size() + kChunk - 1) / kChunk;

    // Calls on(k, i) for every point i of chunk `c` inside the region of a core point k of
    // [first, last): the cheap range test before the exact one.
    auto stream = [&](std::size_t c, std::uint32_t first, std::uint32_t last, auto&& on) {
        const std::size_t end = std::min(cloud.size(), (c + 1) * kChunk);
        std::uint64_t last_key = ~std::uint64_t{0};
        std::span<const std::uint32_t> candidates;
        for (std::size_t i = c * kChunk; i < end; ++i) {
            if (!kept(i)) continue;
            const Eigen::Vector3d& p = cloud[i];
            const auto key = index.key_of(p);
            if (!key) continue;
            if (*key != last_key) {  // scans are ordered: neighbours share cells
                last_key = *key;
                candidates = index.regions_in(*key);
            }
            for (std::uint32_t k : candidates)
                if (k >= first && k < last && contains(k, p)) on(k, static_cast<std::uint32_t>(i));
        }
    };
    const auto all = static_cast<std::uint32_t>(cores);

    std::vector<FoundPairs> found(chunks);
    std::vector<std::uint64_t> begin;
    std::vector<std::uint32_t> members;
    // Chunks in the cloud's order: each core point's members stay ascending.
    auto gather = [&](std::uint32_t first) {
        std::vector<std::uint64_t> at(begin.begin(), begin.end() - 1);
        for (auto& out : found) {
            out.for_each([&](std::uint32_t k, std::uint32_t i) { members[at[k - first]++] = i; });
            out.clear();
        }
    };
    auto visit_all = [&](std::size_t first, std::size_t last) {
        parallel_for(
            last - first,
            [&](std::size_t j) {
                visit(first + j, std::span<const std::uint32_t>(members.data() + begin[j],
                                                                members.data() + begin[j + 1]));
            },
            threads);
    };

    // One pass when every member fits the budget (the usual case for cylinders); a chunk
    // that starts after the budget is exceeded does nothing.
    std::atomic<std::size_t> total{single_pass ? 0 : budget + 1};
    if (single_pass)
        parallel_for(
            chunks,
            [&](std::size_t c) {
                if (total.load(std::memory_order_relaxed) > budget) return;
                auto& out = found[c];
                stream(c, 0, all, [&](std::uint32_t k, std::uint32_t i) { out.add(k, i); });
                total.fetch_add(out.size(), std::memory_order_relaxed);
            },
            threads);
    if (total.load() <= budget) {
        begin.assign(cores + 1, 0);
        for (const auto& out : found)
            out.for_each([&](std::uint32_t k, std::uint32_t) { ++begin[k + 1]; });
        for (std::size_t k = 0; k < cores; ++k) begin[k + 1] += begin[k];
        members.resize(begin[cores]);
        gather(0);
        visit_all(0, cores);
        return;
    }
    for (auto& out : found) out.release();

    // Otherwise count first, then batches of consecutive core points within the budget. A
    // batch's pass skips the chunks whose box misses every region of the batch (in a scan's
    // order, most of them).
    std::vector<std::atomic<std::uint32_t>> counts(cores);
    std::vector<Eigen::AlignedBox3d> chunk_box(chunks);
    parallel_for(
        chunks,
        [&](std::size_t c) {
            const std::size_t end = std::min(cloud.size(), (c + 1) * kChunk);
            for (std::size_t i = c * kChunk; i < end; ++i)
                if (kept(i) && cloud[i].allFinite()) chunk_box[c].extend(cloud[i]);
            stream(c, 0, all, [&](std::uint32_t k, std::uint32_t) {
                counts[k].fetch_add(1, std::memory_order_relaxed);
            });
        },
        threads);
    for (std::size_t first = 0; first < cores;) {
        std::size_t last = first;
        std::uint64_t batch = 0;
        while (last < cores && (last == first || batch + counts[last] <= budget))
            batch += counts[last++];
        begin.assign(last - first + 1, 0);
        for (std::size_t k = first; k < last; ++k)
            begin[k - first + 1] = begin[k - first] + counts[k];
        members.resize(batch);
        if (batch > 0) {
            Eigen::AlignedBox3d batch_box;
            for (std::size_t k = first; k < last; ++k) batch_box.extend(index.box(k));
            parallel_for(
                chunks,
                [&](std::size_t c) {
                    if (!chunk_box[c].intersects(batch_box)) return;
                    auto& out = found[c];
                    stream(c, static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(last),
                           [&](std::uint32_t k, std::uint32_t i) { out.add(k, i); });
                },
                threads);
            gather(static_cast<std::uint32_t>(first));
        }
        visit_all(first, last);
        first = last;
    }
}

}  // namespace tlsmon::m3c2
