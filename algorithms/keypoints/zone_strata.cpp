#include "algorithms/keypoints/zone_strata.hpp"

#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_set>

#include "core/error.hpp"

namespace tlsmon::keypoints {

std::vector<Eigen::Vector3d> wall_cell_centres(std::span<const Eigen::Vector3d> points,
                                               const WallFrame& wall, double cell) {
    if (!(cell > 0)) throw Error("wall cells: the cell size must be positive");
    std::vector<Eigen::Vector3d> out;
    if (!wall.defined()) return out;
    // A cell's key: its two indices along h and v, packed into one 64-bit number.
    std::unordered_set<std::uint64_t> seen;
    for (const Eigen::Vector3d& p : points) {
        const Eigen::Vector3d r = p - wall.centroid;
        const auto i = static_cast<std::int64_t>(std::floor(r.dot(wall.horizontal) / cell));
        const auto j = static_cast<std::int64_t>(std::floor(r.dot(wall.vertical) / cell));
        const std::uint64_t key =
            (static_cast<std::uint64_t>(i) << 32) ^ (static_cast<std::uint64_t>(j) & 0xffffffffu);
        if (!seen.insert(key).second) continue;
        out.push_back(wall.centroid + (double(i) + 0.5) * cell * wall.horizontal +
                      (double(j) + 0.5) * cell * wall.vertical);
    }
    return out;
}

std::vector<float> vertical_angles(std::span<const Eigen::Vector3d> centres,
                                   const Eigen::Vector3d& scanner) {
    std::vector<float> out;
    out.reserve(centres.size());
    for (const Eigen::Vector3d& c : centres) {
        const Eigen::Vector3d d = c - scanner;
        out.push_back(static_cast<float>(std::atan2(d.z(), std::hypot(d.x(), d.y()))));
    }
    return out;
}

SegmentDisplacement stratified_displacement(std::span<const KeypointMatch> matches,
                                            std::span<const OutlierFilter> removed_by,
                                            const WallFrame& wall,
                                            std::span<const float> cell_elevations,
                                            const StratifiedParameters& parameters) {
    std::vector<KeypointMatch> zone(matches.begin(), matches.end());
    for (auto& m : zone) m.segment = 0;
    // An undefined wall: the plain mean, its frame fitted to the kept matches.
    SegmentDisplacement out =
        segment_displacement(zone, removed_by, 0, parameters.segment,
                             wall.defined() ? std::optional<WallFrame>(wall) : std::nullopt);
    if (!out.defined() || !wall.defined() || cell_elevations.empty()) return out;

    // Each band's area (in cells: every cell has the same area) and kept matches.
    std::map<int, std::pair<double, std::size_t>> bands;
    double total = 0;
    for (const float e : cell_elevations) {
        bands[vertical_angle_band(e, parameters.band_width)].first += 1;
        total += 1;
    }
    for (std::size_t i = 0; i < matches.size(); ++i)
        if (removed_by[i] == OutlierFilter::none) bands[matches[i].segment].second += 1;
    // Strata: neighbouring bands joined, from the lowest, until each holds enough kept
    // matches (collapsed strata, Cochran 1977 §5A.12); a remainder joins the last one, and a
    // band without a match counts with its neighbours.
    std::map<int, int> stratum_of;
    std::vector<double> area;
    std::size_t held = 0;
    double covered = 0;
    for (const auto& [band, figures] : bands) {
        if (area.empty() || held >= parameters.min_stratum_matches) {
            area.push_back(0);
            held = 0;
        }
        stratum_of[band] = static_cast<int>(area.size()) - 1;
        area.back() += figures.first;
        held += figures.second;
        if (figures.second > 0) covered += figures.first;
    }
    if (held < parameters.min_stratum_matches && area.size() > 1) {
        const int last = static_cast<int>(area.size()) - 1;
        for (auto& [band, s] : stratum_of)
            if (s == last) s = last - 1;
        area[area.size() - 2] += area.back();
        area.pop_back();
    }
    for (std::size_t i = 0; i < zone.size(); ++i) zone[i].segment = stratum_of[matches[i].segment];
    SegmentParameters per_stratum = parameters.segment;
    per_stratum.min_matches = 2;
    std::vector<SegmentDisplacement> strata;
    for (std::size_t k = 0; k < area.size(); ++k) {
        strata.push_back(
            segment_displacement(zone, removed_by, static_cast<int>(k), per_stratum, wall));
        if (!strata.back().defined() || !strata.back().along.allFinite()) return out;
    }
    // The variance per kept match within the strata (n·SE², each a trimmed mean's;
    // segment_displacement.hpp), pooled: a stratum of a few matches never claims to scatter
    // less than the zone's strata do together.
    const auto per_match = [](const Eigen::Vector3d& se, double n) { return n * se.cwiseAbs2(); };
    Eigen::Vector3d pooled = Eigen::Vector3d::Zero(), along_pooled = Eigen::Vector3d::Zero();
    double dof = 0;
    for (const SegmentDisplacement& d : strata) {
        const double n = static_cast<double>(d.count);
        pooled += (n - 1) * per_match(d.standard_error, n);
        along_pooled += (n - 1) * per_match(d.along_standard_error, n);
        dof += n - 1;
    }
    if (!(dof > 0)) return out;
    pooled /= dof;
    along_pooled /= dof;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), variance = Eigen::Vector3d::Zero();
    Eigen::Vector3d along = Eigen::Vector3d::Zero(), along_variance = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < strata.size(); ++k) {
        const SegmentDisplacement& d = strata[k];
        const double w = area[k] / total, n = static_cast<double>(d.count);
        mean += w * d.mean;
        variance += w * w * per_match(d.standard_error, n).cwiseMax(pooled) / n;
        along += w * d.along;
        along_variance += w * w * per_match(d.along_standard_error, n).cwiseMax(along_pooled) / n;
    }
    out.mean = mean;
    out.standard_error = variance.cwiseSqrt();
    out.along = along;
    out.along_standard_error = along_variance.cwiseSqrt();
    out.covered_area_share = covered / total;
    return out;
}

}  // namespace tlsmon::keypoints
