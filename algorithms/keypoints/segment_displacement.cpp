#include "algorithms/keypoints/segment_displacement.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tlsmon::keypoints {
namespace {

// Points whose spread across their main direction is below this share of the spread along
// it lie (for a plane fit) on one line.
constexpr double kCollinearRatio = 1e-3;
// sin 1°: a normal closer than this to up leaves no horizontal direction in the plane.
const double kHorizontalSurfaceSine = std::sin(std::numbers::pi / 180.0);

// Mean, sample standard deviation (n − 1) and standard error of the columns' rows.
struct Moments {
    Eigen::Vector3d mean, std_dev, standard_error;
};
Moments moments(const std::vector<Eigen::Vector3d>& values) {
    const double n = static_cast<double>(values.size());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& v : values) sum += v;
    const Eigen::Vector3d mean = sum / n;
    Eigen::Vector3d squares = Eigen::Vector3d::Zero();
    for (const auto& v : values) squares += (v - mean).cwiseAbs2();  // two passes: no cancellation
    const Eigen::Vector3d std_dev = (squares / (n - 1)).cwiseSqrt();
    return {mean, std_dev, std_dev / std::sqrt(n)};
}

}  // namespace

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
    for (std::size_t i = 0; i < matches.size(); ++i) {
        if (matches[i].segment != segment) continue;
        ++result.matches;
        if (removed_by[i] != OutlierFilter::none) continue;
        const Eigen::Vector3d d = matches[i].displacement();
        if (!d.allFinite() || !matches[i].reference_point.allFinite())
            throw Error("segment displacement: keypoint match " + std::to_string(i) +
                        " has a non-finite point");
        vectors.push_back(d);
        reference_points.push_back(matches[i].reference_point);
    }
    result.count = vectors.size();
    if (result.count < parameters.min_matches) {
        result.undefined_reason = std::to_string(result.count) + " matches kept of " +
                                  std::to_string(result.matches) + ", fewer than min_matches " +
                                  std::to_string(parameters.min_matches);
        return result;
    }
    const Moments xyz = moments(vectors);
    result.mean = xyz.mean;
    result.std_dev = xyz.std_dev;
    result.standard_error = xyz.standard_error;

    result.wall =
        wall ? *wall : fit_wall_frame(reference_points, parameters.orientation, parameters.up);
    if (result.wall.defined()) {
        Eigen::Matrix3d to_wall;  // rows: n, h, v
        to_wall.row(0) = result.wall.normal.transpose();
        to_wall.row(1) = result.wall.horizontal.transpose();
        to_wall.row(2) = result.wall.vertical.transpose();
        std::vector<Eigen::Vector3d> along(vectors.size());
        for (std::size_t j = 0; j < vectors.size(); ++j) along[j] = to_wall * vectors[j];
        const Moments wall_moments = moments(along);
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
