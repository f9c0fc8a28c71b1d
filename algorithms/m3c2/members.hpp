#pragma once
// The points of a cloud inside each core point's region, found by streaming the cloud once
// through a RegionIndex (region_index.hpp). Each core point's members come in the cloud's
// order whatever the number of threads, so results built from them do not depend on it.
// When the members of all core points would not fit in `budget` entries, the core points are
// taken in consecutive batches, each with its own pass over the cloud.
#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
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
template <class Contains, class Visit>
void for_each_core_with_members(const std::vector<Eigen::Vector3d>& cloud,
                                const RegionIndex& index, std::size_t cores, Contains&& contains,
                                Visit&& visit, unsigned threads = 0,
                                std::size_t budget = kMemberBudget) {
    if (cloud.size() > std::size_t{0xFFFFFFFF})
        throw Error("m3c2: a cloud of more than 2^32 - 1 points");
    constexpr std::size_t kChunk = std::size_t{1} << 16;
    const std::size_t chunks = (cloud.size() + kChunk - 1) / kChunk;

    // Calls on(k, i) for every point i of chunk `c` inside the region of core point k.
    auto stream = [&](std::size_t c, auto&& on) {
        const std::size_t end = std::min(cloud.size(), (c + 1) * kChunk);
        std::uint64_t last_key = ~std::uint64_t{0};
        std::span<const std::uint32_t> candidates;
        for (std::size_t i = c * kChunk; i < end; ++i) {
            const Eigen::Vector3d& p = cloud[i];
            const auto key = index.key_of(p);
            if (!key) continue;
            if (*key != last_key) {  // scans are ordered: neighbours share cells
                last_key = *key;
                candidates = index.regions_in(*key);
            }
            for (std::uint32_t k : candidates)
                if (contains(k, p)) on(k, static_cast<std::uint32_t>(i));
        }
    };

    std::vector<std::atomic<std::uint32_t>> counts(cores);
    parallel_for(
        chunks,
        [&](std::size_t c) {
            stream(c, [&](std::uint32_t k, std::uint32_t) {
                counts[k].fetch_add(1, std::memory_order_relaxed);
            });
        },
        threads);

    std::vector<std::vector<std::uint32_t>> found(chunks);  // per chunk: (core, point) pairs
    std::vector<std::uint64_t> begin;
    std::vector<std::uint32_t> members;
    for (std::size_t first = 0; first < cores;) {
        std::size_t last = first;
        std::uint64_t total = 0;
        while (last < cores && (last == first || total + counts[last] <= budget))
            total += counts[last++];
        begin.assign(last - first + 1, 0);
        for (std::size_t k = first; k < last; ++k)
            begin[k - first + 1] = begin[k - first] + counts[k];
        members.resize(total);
        if (total > 0) {
            parallel_for(
                chunks,
                [&](std::size_t c) {
                    auto& out = found[c];
                    out.clear();
                    stream(c, [&](std::uint32_t k, std::uint32_t i) {
                        if (k < first || k >= last) return;
                        out.push_back(k);
                        out.push_back(i);
                    });
                },
                threads);
            // Chunks in the cloud's order: each core point's members stay ascending.
            std::vector<std::uint64_t> at(begin.begin(), begin.end() - 1);
            for (auto& out : found) {
                for (std::size_t j = 0; j < out.size(); j += 2) members[at[out[j] - first]++] = out[j + 1];
                std::vector<std::uint32_t>().swap(out);
            }
        }
        parallel_for(
            last - first,
            [&](std::size_t j) {
                visit(first + j, std::span<const std::uint32_t>(members.data() + begin[j],
                                                                 members.data() + begin[j + 1]));
            },
            threads);
        first = last;
    }
}

}  // namespace tlsmon::m3c2
