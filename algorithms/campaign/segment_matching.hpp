#pragma once
// Which of the reference's segments a campaign segment is (the procedure: the TLS
// reference segmented as the campaign is, the two matched by overlap after the global
// registration). Each campaign point, once registered, lands on the reference's surface: the
// reference segment of its nearest reference point is where it lies. A campaign segment is
// the reference segment most of its points lie on, when that is at least `min_overlap` of
// them; its overlap is that share. So a campaign's segments carry the reference's numbering,
// and one element of the structure (a pier face, the deck's soffit) can be followed from
// campaign to campaign although each campaign is segmented on its own.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace tlsmon::campaign {

struct SegmentMatch {
    std::int32_t reference = -1;  // the reference segment; −1: none holds min_overlap
    double overlap = 0;           // the share of the segment's points on it
    std::size_t sampled = 0;      // points looked at
};

// `nearest(x)`: the reference point nearest x (−1: none near enough; such a point counts
// against every reference segment); `reference_segment`: per reference point (−1: none, e.g.
// ground). `segment`: per campaign point, its segment 0 … segments − 1 (−1: none). At most
// `samples` points of each segment are looked at, taken evenly. The result does not depend on
// `threads` (0: every core).
std::vector<SegmentMatch> match_segments(
    std::span<const Eigen::Vector3d> points, std::span<const std::int32_t> segment,
    std::size_t segments, const std::function<std::int64_t(const Eigen::Vector3d&)>& nearest,
    std::span<const std::int32_t> reference_segment, double min_overlap, std::size_t samples,
    unsigned threads = 0);

}  // namespace tlsmon::campaign
