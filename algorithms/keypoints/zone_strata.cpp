#include "algorithms/keypoints/zone_strata.hpp"

#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
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

namespace {

double vertical_angle(const Eigen::Vector3d& p, const Eigen::Vector3d& scanner) {
    const Eigen::Vector3d d = p - scanner;
    return std::atan2(d.z(), std::hypot(d.x(), d.y()));
}

// A stratum's line: the least-squares slope b of its kept matches' vectors on their vertical
// angle e about their mean ē, and b's cluster-robust covariance
//   G/(G − 1)·Σ_c g_c·g_cᵀ / S_ee²,   g_c = Σ_{i ∈ c} (e_i − ē)·r_i,   S_ee = Σ (e_i − ē)²,
// r the residuals about the line (the sandwich of a regression's slope, Cameron & Miller
// 2015; each g_c with its leverage, below). None with fewer than three kept matches or all
// at one angle.
struct StratumLine {
    double mean_angle = 0;
    Eigen::Vector3d slope = Eigen::Vector3d::Zero();
    Eigen::Matrix3d slope_covariance = Eigen::Matrix3d::Zero();
};

std::optional<StratumLine> stratum_line(std::span<const KeypointMatch> zone,
                                        std::span<const OutlierFilter> removed_by,
                                        std::span<const double> angle, int stratum,
                                        double cluster_px) {
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < zone.size(); ++i)
        if (zone[i].segment == stratum && removed_by[i] == OutlierFilter::none) kept.push_back(i);
    if (kept.size() < 3) return std::nullopt;
    const double n = static_cast<double>(kept.size());
    StratumLine line;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const std::size_t i : kept)
        line.mean_angle += angle[i] / n, mean += zone[i].displacement() / n;
    double see = 0;
    Eigen::Vector3d sed = Eigen::Vector3d::Zero();
    for (const std::size_t i : kept) {
        const double de = angle[i] - line.mean_angle;
        see += de * de;
        sed += de * (zone[i].displacement() - mean);
    }
    if (!(see > 0)) return std::nullopt;
    line.slope = sed / see;
    struct Score {
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        double leverage = 0;
    };
    std::map<std::uint64_t, Score> scores;
    for (const std::size_t i : kept) {
        const double de = angle[i] - line.mean_angle;
        Score& c = scores[match_cluster(zone[i], i, cluster_px)];
        c.g += de * (zone[i].displacement() - mean - de * line.slope);
        c.leverage += 1 / n + de * de / see;
    }
    // Each cluster's score over √(1 − h_c), h_c its matches' leverages on the line: the
    // residuals of a fit are smaller than its errors by that much, most at the ends that hold
    // the slope (Bell & McCaffrey 2002's CR2, in the diagonal form of a cluster).
    for (const auto& [c, score] : scores)
        line.slope_covariance +=
            score.g * score.g.transpose() / std::max(1.0 - score.leverage, 0.05);
    const double groups = static_cast<double>(scores.size());
    if (groups > 1) line.slope_covariance *= groups / (groups - 1);
    line.slope_covariance /= see * see;
    return line;
}

}  // namespace

std::vector<float> vertical_angles(std::span<const Eigen::Vector3d> centres,
                                   const Eigen::Vector3d& scanner) {
    std::vector<float> out;
    out.reserve(centres.size());
    for (const Eigen::Vector3d& c : centres)
        out.push_back(static_cast<float>(vertical_angle(c, scanner)));
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
    std::vector<double> area;  // in cells
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
    std::vector<double> cells_elevation(area.size(), 0.0);
    for (const float e : cell_elevations)
        cells_elevation[static_cast<std::size_t>(
            stratum_of[vertical_angle_band(e, parameters.band_width)])] += e;
    for (std::size_t k = 0; k < area.size(); ++k) cells_elevation[k] /= area[k];
    // Within a stratum the matches need not sit where its area is (they crowd where the
    // texture is resolved best: on `hochmosel`'s strip 0.3–0.9 m below the middle of its 10 m
    // zones), and over a face that bends the displacement changes across it, so the stratum's
    // plain mean stands for the matches' height. The separate regression estimator of a
    // stratified sample (Cochran 1977, §7.10) moves each stratum's mean along its line on the
    // vertical angle to its cells' mean angle Ē_s: d̂_s = d̄_s + b_s·(Ē_s − ē_s), of variance
    // that of the mean about the line plus (Ē_s − ē_s)²·Var(b_s). The matches are taken about
    // their stratum's line (every match, the removed ones for the trimmed mean's Winsorized
    // values): the kept mean stays, and its standard error is the residuals', not the
    // displacement's change across the stratum.
    std::vector<double> angle;  // the matches', taken as the cells' were
    for (const auto& m : zone)
        angle.push_back(vertical_angle(m.reference_point, parameters.scanner));
    std::vector<std::optional<StratumLine>> lines;
    for (std::size_t k = 0; k < area.size(); ++k)
        lines.push_back(stratum_line(zone, removed_by, angle, static_cast<int>(k),
                                     parameters.segment.cluster_px));
    for (std::size_t i = 0; i < zone.size(); ++i)
        if (const auto& line = lines[static_cast<std::size_t>(zone[i].segment)])
            zone[i].point -= (angle[i] - line->mean_angle) * line->slope;
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
    const Eigen::Matrix3d to_wall = wall.rows();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), variance = Eigen::Vector3d::Zero();
    Eigen::Vector3d along = Eigen::Vector3d::Zero(), along_variance = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < strata.size(); ++k) {
        const SegmentDisplacement& d = strata[k];
        const double w = area[k] / total, n = static_cast<double>(d.count);
        Eigen::Vector3d shift = Eigen::Vector3d::Zero(), shift_variance = shift;
        Eigen::Vector3d along_shift = shift, along_shift_variance = shift;
        if (const auto& line = lines[k]) {
            const double to_cells = cells_elevation[k] - line->mean_angle;
            shift = to_cells * line->slope;
            shift_variance = to_cells * to_cells * line->slope_covariance.diagonal();
            along_shift = to_wall * shift;
            along_shift_variance =
                to_cells * to_cells *
                (to_wall * line->slope_covariance * to_wall.transpose()).diagonal();
        }
        mean += w * (d.mean + shift);
        variance += w * w * (per_match(d.standard_error, n).cwiseMax(pooled) / n + shift_variance);
        along += w * (d.along + along_shift);
        along_variance += w * w *
                          (per_match(d.along_standard_error, n).cwiseMax(along_pooled) / n +
                           along_shift_variance);
    }
    out.mean = mean;
    out.standard_error = variance.cwiseSqrt();
    out.along = along;
    out.along_standard_error = along_variance.cwiseSqrt();
    out.covered_area_share = covered / total;
    return out;
}

}  // namespace tlsmon::keypoints
