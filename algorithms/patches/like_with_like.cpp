#include "algorithms/patches/like_with_like.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace tlsmon::patches {

double block_side(double area, std::size_t points) {
    if (points == 0 || !(area > 0)) return kBlock;
    return std::max(kBlock, std::sqrt(kBlockPoints * area / double(points)));
}

std::vector<BlockMoments> block_moments(const std::vector<Eigen::Vector3f>& uvw,
                                        const std::vector<std::uint8_t>& keep, double side) {
    std::map<std::pair<std::int32_t, std::int32_t>, PlaneMoments> blocks;  // (j, i)
    for (std::size_t k = 0; k < uvw.size(); ++k) {
        if (!keep[k]) continue;
        const auto i = static_cast<std::int32_t>(std::floor(double(uvw[k].x()) / side));
        const auto j = static_cast<std::int32_t>(std::floor(double(uvw[k].y()) / side));
        blocks[{j, i}].add(uvw[k].cast<double>());
    }
    std::vector<BlockMoments> out;
    out.reserve(blocks.size());
    for (const auto& [key, m] : blocks) out.push_back({key.second, key.first, m});
    return out;
}

PlaneMoments total(const std::vector<BlockMoments>& blocks) {
    PlaneMoments sum;
    for (const auto& b : blocks) sum += b.moments;
    return sum;
}

SeenAlike seen_alike(const std::vector<BlockMoments>& reference,
                     const std::vector<BlockMoments>& epoch) {
    const PlaneMoments reference_total = total(reference), epoch_total = total(epoch);
    SeenAlike out{reference_total, epoch_total, false, reference_total, epoch_total};
    if (reference.empty()) return out;
    // Each epoch block's block in the reference (both in (j, i) order), or none.
    const auto before = [](const BlockMoments& x, const BlockMoments& y) {
        return x.j != y.j ? x.j < y.j : x.i < y.i;
    };
    std::vector<double> n2(reference.size(), 0.0);
    std::vector<std::ptrdiff_t> in_reference(epoch.size(), -1);
    double outside = 0.0;  // the epoch's points in blocks the reference has none in
    for (std::size_t e = 0, r = 0; e < epoch.size(); ++e) {
        while (r < reference.size() && before(reference[r], epoch[e])) ++r;
        if (r < reference.size() && !before(epoch[e], reference[r])) {
            n2[r] = epoch[e].moments.m;
            in_reference[e] = std::ptrdiff_t(r);
        } else {
            outside += epoch[e].moments.m;
        }
    }
    // The epoch's density relative to the reference's where it saw the patch at all.
    std::vector<double> ratio;
    for (std::size_t k = 0; k < reference.size(); ++k)
        if (n2[k] > 0) ratio.push_back(n2[k] / reference[k].moments.m);
    if (ratio.empty()) return out;  // nothing seen: too few epoch points
    const auto upper = ratio.begin() + long(3 * (ratio.size() - 1) / 4);
    std::nth_element(ratio.begin(), upper, ratio.end());
    const double rho = *upper;
    std::vector<std::uint8_t> alike(reference.size());
    double unseen = 0.0;
    for (std::size_t k = 0; k < reference.size(); ++k) {
        const double e = rho * reference[k].moments.m;
        alike[k] = n2[k] > 0 && (n2[k] >= 0.5 * e || n2[k] >= e - 3.0 * std::sqrt(e));
        if (!alike[k]) unseen += reference[k].moments.m;
    }
    if (unseen <= kUnseenShare * out.reference.m && outside <= kUnseenShare * out.epoch.m) {
        return out;
    }
    // A block next to one not seen alike may have been seen in part (the edge of what the epoch
    // saw runs through it): left out too.
    std::set<std::pair<std::int32_t, std::int32_t>> unseen_places;
    for (std::size_t k = 0; k < reference.size(); ++k)
        if (!alike[k]) unseen_places.insert({reference[k].i, reference[k].j});
    for (std::size_t k = 0; k < reference.size(); ++k)
        for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj)
                if (unseen_places.count({reference[k].i + di, reference[k].j + dj})) alike[k] = 0;
    SeenAlike part{{}, {}, true, reference_total, epoch_total};
    for (std::size_t k = 0; k < reference.size(); ++k)
        if (alike[k]) part.reference += reference[k].moments;
    for (std::size_t e = 0; e < epoch.size(); ++e)
        if (in_reference[e] >= 0 && alike[std::size_t(in_reference[e])])
            part.epoch += epoch[e].moments;
    return part;
}

PatchResult compared_distance(const std::vector<BlockMoments>& reference,
                              const std::vector<BlockMoments>& epoch, double registration_sigma,
                              const Parameters& parameters) {
    const SeenAlike seen = seen_alike(reference, epoch);
    // Not partial: `seen` holds the two totals.
    if (!seen.partial) {
        return patch_distance(fit_plane(seen.reference), fit_plane(seen.epoch), registration_sigma,
                              parameters);
    }
    const PatchResult whole =
        patch_distance(fit_plane(seen.reference_total), fit_plane(seen.epoch_total),
                       registration_sigma, parameters);
    if (whole.outcome == PatchOutcome::few_reference_points ||
        whole.outcome == PatchOutcome::rough) {
        return whole;  // the reference refused on its whole plane
    }
    PatchResult part = patch_distance(fit_plane(seen.reference), fit_plane(seen.epoch),
                                      registration_sigma, parameters);
    part.partial = true;
    if (part.outcome == PatchOutcome::few_reference_points || part.outcome == PatchOutcome::rough)
        part.outcome = PatchOutcome::partly_seen;
    return part;
}

}  // namespace tlsmon::patches
