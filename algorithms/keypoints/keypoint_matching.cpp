#include "algorithms/keypoints/keypoint_matching.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "core/error.hpp"

namespace tlsmon::keypoints {

namespace {

// Keypoints sorted by elevation, so that the candidates of a query lie in one band.
class ElevationIndex {
  public:
    explicit ElevationIndex(const std::vector<AngularPosition>& positions)
        : positions_(positions), order_(positions.size()) {
        std::iota(order_.begin(), order_.end(), std::size_t{0});
        std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
            return positions_[a].elevation < positions_[b].elevation;
        });
    }

    // Calls f(index) for every keypoint within `radius` of `q`.
    template <class F>
    void within(const AngularPosition& q, double radius, F&& f) const {
        auto first =
            std::lower_bound(order_.begin(), order_.end(), q.elevation - radius,
                             [&](std::size_t i, double e) { return positions_[i].elevation < e; });
        const double r2 = radius * radius;
        for (auto it = first; it != order_.end(); ++it) {
            const AngularPosition& p = positions_[*it];
            if (p.elevation > q.elevation + radius) break;
            const double da = wrapped_difference(p.azimuth, q.azimuth);
            const double de = p.elevation - q.elevation;
            if (da * da + de * de <= r2) f(*it);
        }
    }

  private:
    const std::vector<AngularPosition>& positions_;
    std::vector<std::size_t> order_;
};

void check_sets(const Descriptors& a, const Descriptors& b) {
    if (a.binary != b.binary || a.length != b.length)
        throw Error("keypoint matching: the two descriptor sets differ in kind or length");
}

}  // namespace

std::vector<AngularPosition> angular_positions(const SphericalImages& images,
                                               const std::vector<Keypoint>& keypoints) {
    std::vector<AngularPosition> out;
    out.reserve(keypoints.size());
    for (const auto& k : keypoints)
        out.push_back({images.azimuth_at(k.column), images.elevation_at(k.row)});
    return out;
}

namespace {

double unchecked_distance(const Descriptors& a, std::size_t i, const Descriptors& b,
                          std::size_t j) {
    const std::size_t n = a.length;
    if (a.binary) {
        const std::uint8_t* x = a.bits.data() + i * n;
        const std::uint8_t* y = b.bits.data() + j * n;
        int bits = 0;
        std::size_t k = 0;
        for (; k + 8 <= n; k += 8) {
            std::uint64_t u, v;
            std::memcpy(&u, x + k, 8);
            std::memcpy(&v, y + k, 8);
            bits += std::popcount(u ^ v);
        }
        for (; k < n; ++k) bits += std::popcount(static_cast<unsigned>(x[k] ^ y[k]));
        return bits;
    }
    const float* x = a.values.data() + i * n;
    const float* y = b.values.data() + j * n;
    double s = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const double d = static_cast<double>(x[k]) - static_cast<double>(y[k]);
        s += d * d;
    }
    return std::sqrt(s);
}

}  // namespace

double descriptor_distance(const Descriptors& a, std::size_t i, const Descriptors& b,
                           std::size_t j) {
    check_sets(a, b);
    if (i >= a.count() || j >= b.count())
        throw Error("keypoint matching: descriptor index out of range");
    return unchecked_distance(a, i, b, j);
}

double window_radius_at(const MatchingParameters& p, double range) {
    if (!(range > 0.0) || !std::isfinite(range)) return p.window_radius;
    return std::max(p.window_radius, p.window_m / range);
}

std::vector<KeypointPair> match_keypoints(const std::vector<AngularPosition>& reference,
                                          const Descriptors& reference_descriptors,
                                          const std::vector<AngularPosition>& epoch,
                                          const Descriptors& epoch_descriptors,
                                          const MatchingParameters& p,
                                          std::span<const double> reference_ranges) {
    if (reference.size() != reference_descriptors.count() ||
        epoch.size() != epoch_descriptors.count())
        throw Error("keypoint matching: keypoints and descriptors differ in number");
    if (!reference_ranges.empty() && reference_ranges.size() != reference.size())
        throw Error("keypoint matching: " + std::to_string(reference_ranges.size()) +
                    " ranges for " + std::to_string(reference.size()) + " reference keypoints");
    if (!(p.window_radius > 0.0)) throw Error("keypoint matching: the window radius must be > 0");
    if (!(p.window_m >= 0.0)) throw Error("keypoint matching: window_m must be >= 0");
    const auto radius_of = [&](std::size_t i) {
        return reference_ranges.empty() ? p.window_radius
                                        : window_radius_at(p, reference_ranges[i]);
    };
    if (!(p.ratio >= 0.0 && p.ratio <= 1.0))
        throw Error("keypoint matching: the ratio must lie in [0, 1] (0: no ratio test)");
    if (reference.empty() || epoch.empty()) return {};
    check_sets(reference_descriptors, epoch_descriptors);

    const ElevationIndex epoch_index(epoch);
    std::vector<KeypointPair> pairs;
    for (std::size_t i = 0; i < reference.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        double second = best;
        std::size_t winner = 0;
        epoch_index.within(reference[i], radius_of(i), [&](std::size_t j) {
            const double d = unchecked_distance(reference_descriptors, i, epoch_descriptors, j);
            if (d < best) {
                second = best;
                best = d;
                winner = j;
            } else if (d < second) {
                second = d;
            }
        });
        if (!std::isfinite(best)) continue;
        if (p.ratio > 0.0 && std::isfinite(second) && !(best < p.ratio * second)) continue;
        pairs.push_back({i, winner, best});
    }
    if (!p.mutual) return pairs;

    // Mutual: no reference keypoint within the radius of the epoch keypoint is strictly
    // nearer to it in descriptor space (ties, common in Hamming distance, do not break it).
    const ElevationIndex reference_index(reference);
    std::vector<KeypointPair> mutual;
    for (const auto& pair : pairs) {
        bool nearest = true;
        reference_index.within(epoch[pair.epoch], radius_of(pair.reference), [&](std::size_t i) {
            if (nearest && unchecked_distance(reference_descriptors, i, epoch_descriptors,
                                              pair.epoch) < pair.distance)
                nearest = false;
        });
        if (nearest) mutual.push_back(pair);
    }
    return mutual;
}

}  // namespace tlsmon::keypoints
