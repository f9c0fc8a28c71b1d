#include "algorithms/keypoints/segment_displacement.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>

#include "core/error.hpp"

namespace tlsmon::keypoints {
namespace {

// Points whose spread across their main direction is below this share of the spread along
// it lie (for a plane fit) on one line.
constexpr double kCollinearRatio = 1e-3;
// sin 1°: a normal closer than this to up leaves no horizontal direction in the plane.
const double kHorizontalSurfaceSine = std::sin(std::numbers::pi / 180.0);

// The kept values' mean and sample standard deviation (n − 1), and the standard error of
// that mean as the outlier filters made it. The filters keep the values near the segment's
// own median, so the kept mean is a trimmed mean and inherits the median's scatter: the kept
// values' spread over √n understates it (on the `pier` faces 2–3 times; docs/keypoints.md,
// "The matches' own σ"). Its variance is a trimmed mean's (Tukey & McLaughlin 1963; Wilcox
// 2012, "Introduction to Robust Estimation", §3.6), from the Winsorized values of every
// match of the segment — a removed value set to the nearest of the kept extremes:
//   Var = G/(G − 1) · Σ_c (Σ_{i ∈ c} (W_i − W̄))² / n²,   n the kept count,
// the sum over the G clusters c of matches that err together (their refinement patches
// overlap; the cluster-robust form with its small-sample factor, Cameron & Miller 2015).
// Without a filter and with every match its own cluster this is s²/n.
struct Moments {
    Eigen::Vector3d mean, std_dev, standard_error;
};
Moments moments(const std::vector<Eigen::Vector3d>& all, const std::vector<bool>& kept,
                const std::vector<std::uint64_t>& cluster) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d high = -low;
    double n = 0;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (!kept[i]) continue;
        sum += all[i], n += 1;
        low = low.cwiseMin(all[i]), high = high.cwiseMax(all[i]);
    }
    const Eigen::Vector3d mean = sum / n;
    Eigen::Vector3d squares = Eigen::Vector3d::Zero(), winsorized_mean = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> winsorized(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (kept[i]) squares += (all[i] - mean).cwiseAbs2();  // two passes: no cancellation
        winsorized[i] = all[i].cwiseMax(low).cwiseMin(high);
        winsorized_mean += winsorized[i];
    }
    winsorized_mean /= static_cast<double>(all.size());
    std::unordered_map<std::uint64_t, Eigen::Vector3d> deviations;
    for (std::size_t i = 0; i < all.size(); ++i)
        deviations.try_emplace(cluster[i], Eigen::Vector3d::Zero()).first->second +=
            winsorized[i] - winsorized_mean;
    Eigen::Vector3d variance = Eigen::Vector3d::Zero();
    for (const auto& [c, d] : deviations) variance += d.cwiseAbs2();
    const double g = static_cast<double>(deviations.size());
    variance *= g > 1 ? g / (g - 1) : 1.0;
    return {mean, (squares / (n - 1)).cwiseSqrt(), variance.cwiseSqrt() / n};
}

}  // namespace

std::uint64_t match_cluster(const KeypointMatch& m, std::size_t index, double cluster_px) {
    if (!(cluster_px > 0)) return index;
    const auto cell = [&](double px) {
        return static_cast<std::uint64_t>(
            static_cast<std::uint32_t>(static_cast<std::int32_t>(std::floor(px / cluster_px))));
    };
    return (static_cast<std::uint64_t>(m.scan) << 56) ^ (cell(m.reference_row) << 28) ^
           cell(m.reference_column);
}

WallFrame fit_wall_frame(std::span<const Eigen::Vector3d> points,
                         const m3c2::Orientation& orientation, const Eigen::Vector3d& up) {
    if (!up.allFinite() || up.isZero(0.0)) throw Error("wall frame: the up direction is zero");
    WallFrame frame;
    frame.points = points.size();
    if (points.size() < 3) {
        frame.undefined_reason =
            std::to_string(points.size()) + " reference points: a plane needs at least 3";
        return frame;
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& p : points) {
        if (!p.allFinite()) throw Error("wall frame: a reference point is not finite");
        sum += p;
    }
    const Eigen::Vector3d centroid = sum / static_cast<double>(points.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto& p : points)
        covariance.noalias() += (p - centroid) * (p - centroid).transpose();
    covariance /= static_cast<double>(points.size());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);  // ascending
    if (!(l[2] > 0.0) || std::sqrt(l[1]) < kCollinearRatio * std::sqrt(l[2])) {
        frame.undefined_reason = "reference points (nearly) on one line or at one place";
        return frame;
    }
    Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
    const Eigen::Vector3d towards = orientation.kind == m3c2::Orientation::Kind::vector
                                        ? orientation.value
                                        : Eigen::Vector3d(orientation.value - centroid);
    if (n.dot(towards) < 0.0) n = -n;

    const Eigen::Vector3d u = up.normalized();
    Eigen::Vector3d h = u.cross(n);
    if (h.norm() < kHorizontalSurfaceSine) {
        frame.horizontal_surface = true;
        h = Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(n) * n;
    }
    h.normalize();
    frame.centroid = centroid;
    frame.normal = n;
    frame.horizontal = h;
    frame.vertical = n.cross(h);
    frame.rms = std::sqrt(l[0]);
    return frame;
}

SegmentDisplacement segment_displacement(std::span<const KeypointMatch> matches,
                                         std::span<const OutlierFilter> removed_by, int segment,
                                         const SegmentParameters& parameters,
                                         const std::optional<WallFrame>& wall) {
    if (removed_by.size() != matches.size())
        throw Error("segment displacement: " + std::to_string(removed_by.size()) +
                    " filter marks for " + std::to_string(matches.size()) + " matches");
    if (parameters.min_matches < 2)
        throw Error("segment displacement: min_matches must be >= 2 (a spread needs two)");

    SegmentDisplacement result;
    result.segment = segment;
    std::vector<Eigen::Vector3d> vectors, reference_points;
    std::vector<bool> kept;
    std::vector<std::uint64_t> cluster;
    for (std::size_t i = 0; i < matches.size(); ++i) {
        if (matches[i].segment != segment) continue;
        ++result.matches;
        const Eigen::Vector3d d = matches[i].displacement();
        const bool finite = d.allFinite() && matches[i].reference_point.allFinite();
        if (!finite && removed_by[i] != OutlierFilter::none) continue;  // nothing to Winsorize
        if (!finite)
            throw Error("segment displacement: keypoint match " + std::to_string(i) +
                        " has a non-finite point");
        vectors.push_back(d);
        kept.push_back(removed_by[i] == OutlierFilter::none);
        cluster.push_back(match_cluster(matches[i], i, parameters.cluster_px));
        if (kept.back()) reference_points.push_back(matches[i].reference_point);
    }
    result.count = reference_points.size();
    if (result.count < parameters.min_matches) {
        result.undefined_reason = std::to_string(result.count) + " matches kept of " +
                                  std::to_string(result.matches) + ", fewer than min_matches " +
                                  std::to_string(parameters.min_matches);
        return result;
    }
    const Moments xyz = moments(vectors, kept, cluster);
    result.mean = xyz.mean;
    result.std_dev = xyz.std_dev;
    result.standard_error = xyz.standard_error;

    result.wall =
        wall ? *wall : fit_wall_frame(reference_points, parameters.orientation, parameters.up);
    if (result.wall.defined()) {
        const Eigen::Matrix3d to_wall = result.wall.rows();
        std::vector<Eigen::Vector3d> along(vectors.size());
        for (std::size_t j = 0; j < vectors.size(); ++j) along[j] = to_wall * vectors[j];
        const Moments wall_moments = moments(along, kept, cluster);
        result.along = wall_moments.mean;
        result.along_std_dev = wall_moments.std_dev;
        result.along_standard_error = wall_moments.standard_error;
    }
    return result;
}

int vertical_angle_band(double elevation, double width) {
    if (!(width > 0) || !(width <= std::numbers::pi))
        throw Error("vertical-angle bands: width must be in (0, 180°], got " +
                    std::to_string(width * 180 / std::numbers::pi) + "°");
    const double half_pi = std::numbers::pi / 2;
    if (!std::isfinite(elevation) || elevation < -half_pi || elevation > half_pi)
        throw Error("vertical-angle bands: vertical angle " + std::to_string(elevation) +
                    " rad is outside [−π/2, π/2]");
    // The number of bands, ceil(π / width), not fooled by rounding when width divides 180°.
    const int last = static_cast<int>(std::ceil(std::numbers::pi / width - 1e-9)) - 1;
    const int band = static_cast<int>(std::floor((elevation + half_pi) / width));
    return std::min(band, last);
}

std::pair<double, double> vertical_angle_band_bounds(int band, double width) {
    const double lower = -std::numbers::pi / 2 + band * width;
    return {lower, lower + width};
}

std::vector<int> vertical_angle_bands(std::span<const KeypointMatch> matches, double width) {
    std::vector<int> bands(matches.size());
    for (std::size_t i = 0; i < matches.size(); ++i) {
        try {
            bands[i] = vertical_angle_band(matches[i].reference_elevation, width);
        } catch (const Error& e) {
            throw Error("keypoint match " + std::to_string(i) + ": " + e.what());
        }
    }
    return bands;
}

}  // namespace tlsmon::keypoints
