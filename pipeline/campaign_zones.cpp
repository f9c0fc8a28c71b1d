#include "pipeline/campaign_zones.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <unordered_map>

#include "algorithms/cell_key.hpp"
#include "core/statistics.hpp"

namespace tlsmon {

namespace {

// √(π/2): the median's standard error over the mean's for normal errors (Kendall & Stuart,
// the asymptotic variance πσ²/2n of the sample median).
constexpr double kMedianEfficiency = 1.2533141373155003;

// The segment's registration error along n at a point r from its centroid, first order:
// δ = t·n + (ω × r)·n = t·n + ω·(r × n), with the parameters' σ taken as independent (the
// stored σ are the marginal ones); an unobserved parameter has no σ and adds nothing along a
// surface it does not observe.
double registration_sigma_along(const CampaignSegmentRow& s, const Eigen::Vector3d& r,
                                const Eigen::Vector3d& n) {
    const Eigen::Vector3d lever = r.cross(n);
    double var = 0;
    for (int k = 0; k < 3; ++k) {
        if (s.sigmas[std::size_t(k)]) var += std::pow(lever(k) * *s.sigmas[std::size_t(k)], 2);
        if (s.sigmas[std::size_t(3 + k)]) var += std::pow(n(k) * *s.sigmas[std::size_t(3 + k)], 2);
    }
    return std::sqrt(var);
}

// The cells the segment's own non-rigidity is read in, and the fewest points of a cell.
constexpr double kCell = 1.0;  // m
constexpr std::size_t kCellPoints = 10;
// A cell faces along n when its C2C vectors run within 30° of n (cos 30°).
constexpr double kAlong = 0.866;

struct Columns {
    Eigen::Vector3d origin;
    std::array<const std::vector<float>*, 7> a;
    Eigen::Vector3d point(std::size_t i) const {
        return origin + Eigen::Vector3d((*a[0])[i], (*a[1])[i], (*a[2])[i]);
    }
    Eigen::Vector3d c2c(std::size_t i) const {
        return Eigen::Vector3d((*a[4])[i], (*a[5])[i], (*a[6])[i]);
    }
};

// A 1 m cell of a segment whose surface faces along n: those whose C2C vectors (along the
// reference's local normal) run mainly within 30° of n, by the principal axis of Σ c·cᵀ.
struct Cell {
    double median = 0;    // of −c·n
    double sampling = 0;  // its sampling variance
};

std::vector<Cell> cells_along(const Columns& c, const std::vector<std::size_t>& members,
                              const Eigen::Vector3d& n) {
    // Each point in the cell of its counterpart on the reference (p + c): a cell whose side
    // lies on the surface is split by the reference's noise, not by the campaign point's,
    // which would leave the halves' medians biased outward and inward.
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_key;
    for (const auto i : members) by_key[cell_key(c.point(i) + c.c2c(i), kCell)].push_back(i);
    std::vector<Cell> out;
    for (const auto& [key, indices] : by_key) {
        if (indices.size() < kCellPoints) continue;
        Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
        for (const auto i : indices) scatter += c.c2c(i) * c.c2c(i).transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(scatter);
        if (std::abs(axes.eigenvectors().col(2).dot(n)) < kAlong) continue;
        std::vector<double> d;
        for (const auto i : indices) d.push_back(-c.c2c(i).dot(n));
        const auto [med, mad] = median_and_mad(d);
        out.push_back({med, std::pow(kMedianEfficiency * kMadToSigma * mad, 2) / double(d.size())});
    }
    return out;
}

// σ of the segment's error along n that its rigid registration leaves (a SLAM's drift goes on
// while the walker sees one segment, so the segment is not rigid in the cloud): the robust
// spread of its cells' medians, less their sampling variance (a variance component, as the
// between-cell variance of a one-way random-effects model). Every cell facing along n counts,
// on this face and on the opposite one alike: −c·n is the drift's component along n on both.
// A change of shape in a few cells hardly moves it (MAD).
double nonrigid_sigma(const std::vector<Cell>& cells) {
    std::vector<double> medians, sampling;
    for (const auto& cell : cells) {
        medians.push_back(cell.median);
        sampling.push_back(cell.sampling);
    }
    if (medians.size() < 3) return 0;  // no spread to read
    const auto spread = median_and_mad(medians);
    return std::sqrt(std::max(0.0, std::pow(kMadToSigma * spread.mad, 2) - median(sampling)));
}

}  // namespace

std::vector<ZoneResult> campaign_zone_results(const CampaignPoints& points,
                                              const std::vector<CampaignSegmentRow>& segments,
                                              const std::vector<ZoneShape>& zones, int min_points) {
    std::vector<ZoneResult> out;
    if (points.size() == 0) return out;
    const Columns columns{Eigen::Vector3d(points.origin[0], points.origin[1], points.origin[2]),
                          points.columns()};
    const auto& segment = *columns.a[3];
    std::map<std::int64_t, const CampaignSegmentRow*> registered;
    for (const auto& s : segments) {
        if (s.outcome == "registered" && s.centroid[0]) registered.emplace(s.segment, &s);
    }
    std::map<std::int64_t, std::vector<std::size_t>> members;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const auto s = std::int64_t(std::lround(segment[i]));
        if (registered.count(s) && columns.c2c(i).allFinite()) members[s].push_back(i);
    }
    // Per segment and direction: many zones share a face.
    std::map<std::pair<std::int64_t, std::array<double, 3>>, double> nonrigid;
    for (const auto& zone : zones) {
        if (!zone.normal.allFinite()) continue;  // no direction to measure along
        const Eigen::Vector3d n = zone.normal.normalized();
        std::vector<double> d;
        // Per segment: its points' count and their sum (for the mean lever arm).
        std::map<std::int64_t, std::pair<std::size_t, Eigen::Vector3d>> by_segment;
        for (const auto& [s, indices] : members) {
            for (const auto i : indices) {
                const Eigen::Vector3d p = columns.point(i);
                if (!zone.contains(p)) continue;
                d.push_back(-columns.c2c(i).dot(n));
                auto& [count, sum] =
                    by_segment.try_emplace(s, 0, Eigen::Vector3d::Zero()).first->second;
                ++count;
                sum += p;
            }
        }
        if (d.empty() || d.size() < std::size_t(std::max(min_points, 1))) continue;
        const auto [med, mad] = median_and_mad(d);
        const double count = double(d.size());
        double var = std::pow(kMedianEfficiency * kMadToSigma * mad, 2) / count;
        for (const auto& [s, tally] : by_segment) {
            const CampaignSegmentRow& row = *registered.at(s);
            const Eigen::Vector3d centroid(*row.centroid[0], *row.centroid[1], *row.centroid[2]);
            const double w = double(tally.first) / count;
            const Eigen::Vector3d mean = tally.second / double(tally.first);
            const auto key = std::make_pair(s, std::array<double, 3>{n.x(), n.y(), n.z()});
            auto found = nonrigid.find(key);
            if (found == nonrigid.end())
                found =
                    nonrigid.emplace(key, nonrigid_sigma(cells_along(columns, members.at(s), n)))
                        .first;
            var += w * w *
                   (std::pow(registration_sigma_along(row, mean - centroid, n), 2) +
                    std::pow(found->second, 2));
        }
        const double lod95 = 1.96 * std::sqrt(var);
        out.push_back(ZoneResult{zone.name, kCampaignC2cMedian, med, lod95, std::int64_t(d.size()),
                                 std::abs(med) > lod95});
    }
    return out;
}

}  // namespace tlsmon
