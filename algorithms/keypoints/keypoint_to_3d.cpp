#include "algorithms/keypoints/keypoint_to_3d.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.hpp"

namespace tlsmon::keypoints {

PolarAt polar_at(const SphericalImages& im, double row, double column, const DepthEdge& edge) {
    PolarAt out;
    // The four pixel centres around the position; a position exactly on the last row or
    // column uses the pair before it (its weight on the outer pair is 1).
    if (!(row >= 0.0 && column >= 0.0 && row <= static_cast<double>(im.rows - 1) &&
          column <= static_cast<double>(im.columns - 1)) ||
        im.rows < 2 || im.columns < 2) {
        out.dropped = Dropped::outside;
        return out;
    }
    const auto r0 = std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(row)), im.rows - 2);
    const auto c0 =
        std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(column)), im.columns - 2);
    const double t = row - static_cast<double>(r0);     // along the rows
    const double u = column - static_cast<double>(c0);  // along the columns
    const std::array<Eigen::Index, 4> rr{r0, r0, r0 + 1, r0 + 1};
    const std::array<Eigen::Index, 4> cc{c0, c0 + 1, c0, c0 + 1};
    const std::array<double, 4> w{(1 - t) * (1 - u), (1 - t) * u, t * (1 - u), t * u};
    double lo = 1e300, hi = -1e300, mean = 0;
    for (int k = 0; k < 4; ++k) {
        if (!im.valid(rr[k], cc[k])) {
            out.dropped = Dropped::empty_neighbour;
            return out;
        }
        const double r = im.range(rr[k], cc[k]);
        lo = std::min(lo, r);
        hi = std::max(hi, r);
        mean += r / 4;
    }
    if (hi - lo > std::max(edge.absolute, edge.relative * mean)) {
        out.dropped = Dropped::depth_edge;
        return out;
    }
    const double a0 = im.azimuth(rr[0], cc[0]);
    for (int k = 0; k < 4; ++k) {
        out.polar.range += w[k] * im.range(rr[k], cc[k]);
        // Relative to the first, so that a ±π wrap between the four cannot enter the mean.
        out.polar.azimuth += w[k] * wrapped_difference(im.azimuth(rr[k], cc[k]), a0);
        out.polar.elevation += w[k] * im.elevation(rr[k], cc[k]);
    }
    out.polar.azimuth += a0;
    return out;
}

bool DroppedCounts::count(Dropped d) {
    switch (d) {
        case Dropped::no:
            return false;
        case Dropped::outside:
            ++dropped_outside;
            break;
        case Dropped::empty_neighbour:
            ++dropped_empty_neighbour;
            break;
        case Dropped::depth_edge:
            ++dropped_depth_edge;
            break;
    }
    return true;
}

void set_polar(KeypointMatch& m, const Polar& reference, const Polar& epoch) {
    m.reference_range = reference.range;
    m.range = epoch.range;
    m.reference_azimuth = reference.azimuth;
    m.azimuth = reference.azimuth + wrapped_difference(epoch.azimuth, reference.azimuth);
    m.reference_elevation = reference.elevation;
    m.elevation = epoch.elevation;
}

MatchesIn3d matches_to_3d(const SphericalImages& reference_images,
                          const std::vector<Keypoint>& reference_keypoints,
                          const Eigen::Affine3d& reference_to_project,
                          const SphericalImages& epoch_images,
                          const std::vector<Keypoint>& epoch_keypoints,
                          const Eigen::Affine3d& epoch_to_project,
                          const std::vector<KeypointPair>& pairs, const DepthEdge& edge) {
    MatchesIn3d out;
    out.matches.reserve(pairs.size());
    for (const auto& pair : pairs) {
        if (pair.reference >= reference_keypoints.size() || pair.epoch >= epoch_keypoints.size())
            throw Error("keypoints to 3-D: a pair's index lies outside the keypoints");
        const Keypoint& a = reference_keypoints[pair.reference];
        const Keypoint& b = epoch_keypoints[pair.epoch];
        const PolarAt pa = polar_at(reference_images, a.row, a.column, edge);
        const PolarAt pb =
            pa.dropped == Dropped::no ? polar_at(epoch_images, b.row, b.column, edge) : pa;
        if (out.count(pb.dropped)) continue;
        KeypointMatch m;
        m.reference_row = a.row;
        m.reference_column = a.column;
        m.row = b.row;
        m.column = b.column;
        set_polar(m, pa.polar, pb.polar);
        m.reference_point = reference_to_project * cartesian_of(pa.polar);
        m.point = epoch_to_project * cartesian_of(pb.polar);
        m.descriptor_distance = pair.distance;
        out.matches.push_back(m);
    }
    return out;
}

}  // namespace tlsmon::keypoints
