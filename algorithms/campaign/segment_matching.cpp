#include "algorithms/campaign/segment_matching.hpp"

#include <algorithm>
#include <map>

#include "core/parallel_for.hpp"

namespace tlsmon::campaign {

std::vector<SegmentMatch> match_segments(
    std::span<const Eigen::Vector3d> points, std::span<const std::int32_t> segment,
    std::size_t segments, const std::function<std::int64_t(const Eigen::Vector3d&)>& nearest,
    std::span<const std::int32_t> reference_segment, double min_overlap, std::size_t samples,
    unsigned threads) {
    std::vector<std::vector<std::size_t>> members(segments);
    for (std::size_t i = 0; i < std::min(points.size(), segment.size()); ++i)
        if (segment[i] >= 0 && std::size_t(segment[i]) < segments)
            members[std::size_t(segment[i])].push_back(i);
    // The points looked at, segment by segment, evenly through each.
    std::vector<std::size_t> probe, first(segments + 1);
    for (std::size_t s = 0; s < segments; ++s) {
        first[s] = probe.size();
        const std::size_t n = std::min(members[s].size(), std::max<std::size_t>(samples, 1));
        for (std::size_t k = 0; k < n; ++k) probe.push_back(members[s][k * members[s].size() / n]);
    }
    first[segments] = probe.size();
    std::vector<std::int32_t> landed(probe.size(), -1);  // the reference segment, −1: none
    parallel_for(
        probe.size(),
        [&](std::size_t j) {
            const std::int64_t r = nearest(points[probe[j]]);
            if (r >= 0) landed[j] = reference_segment[std::size_t(r)];
        },
        threads);
    std::vector<SegmentMatch> out(segments);
    for (std::size_t s = 0; s < segments; ++s) {
        std::map<std::int32_t, std::size_t> votes;  // ordered: a tie goes to the lower id
        for (std::size_t j = first[s]; j < first[s + 1]; ++j)
            if (landed[j] >= 0) ++votes[landed[j]];
        auto& m = out[s];
        m.sampled = first[s + 1] - first[s];
        if (m.sampled == 0) continue;
        std::size_t best = 0;
        for (const auto& [label, count] : votes) {
            if (count <= best) continue;
            best = count;
            m.reference = label;
        }
        m.overlap = double(best) / double(m.sampled);
        if (m.overlap < min_overlap) m.reference = -1;
    }
    return out;
}

}  // namespace tlsmon::campaign
