#include "pipeline/pcl_adapter.hpp"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/segmentation/supervoxel_clustering.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <unordered_map>

#include "core/error.hpp"

namespace tlsmon {

namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

// A normal needs this many neighbours, spread in two directions: the second eigenvalue of
// their covariance at least this share of the largest.
constexpr int kMinNeighbours = 6;
constexpr double kMinSpread = 0.05;

// Points (and normals) about `origin`, in float.
Cloud::Ptr to_cloud(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& origin,
                    const std::vector<Eigen::Vector3d>* normals = nullptr) {
    auto cloud = pcl::make_shared<Cloud>();
    cloud->resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        auto& q = (*cloud)[i];
        const Eigen::Vector3d p = points[i] - origin;
        q.x = static_cast<float>(p.x());
        q.y = static_cast<float>(p.y());
        q.z = static_cast<float>(p.z());
        const Eigen::Vector3d n = normals ? (*normals)[i] : Eigen::Vector3d::Zero();
        q.normal_x = static_cast<float>(n.x());
        q.normal_y = static_cast<float>(n.y());
        q.normal_z = static_cast<float>(n.z());
        q.curvature = 0.0f;
    }
    return cloud;
}

// The number of iterations PCL ran (kept protected in pcl::Registration).
class CountingIcp
    : public pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> {
  public:
    int iterations() const { return nr_iterations_; }
};

// Points about `origin`, in float (no normals).
pcl::PointCloud<pcl::PointXYZ>::Ptr xyz_cloud(std::span<const Eigen::Vector3d> points,
                                              const Eigen::Vector3d& origin) {
    auto xyz = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    xyz->resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d p = points[i] - origin;
        (*xyz)[i] = pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z()));
    }
    return xyz;
}

Eigen::Vector3d centroid(std::span<const Eigen::Vector3d> points) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : points) c += p;
    return points.empty() ? c : Eigen::Vector3d(c / static_cast<double>(points.size()));
}

// The smaller spread (rad, a standard deviation) of the neighbours' directions from the
// viewpoint: the middle eigenvalue of their weighted covariance (the smallest lies along the
// mean direction).
template <typename Count>
double direction_spread(std::span<const Eigen::Vector3d> points, const std::vector<int>& k,
                        const Eigen::Vector3d& viewpoint, const Count& count) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double w = 0;
    for (const int j : k) {
        const auto u = static_cast<std::size_t>(j);
        mean += count(u) * (points[u] - viewpoint).normalized();
        w += count(u);
    }
    mean /= w;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const int j : k) {
        const auto u = static_cast<std::size_t>(j);
        const Eigen::Vector3d d = (points[u] - viewpoint).normalized() - mean;
        C += count(u) * d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C / w, Eigen::EigenvaluesOnly);
    return std::sqrt(std::max(0.0, es.eigenvalues()(1)));
}

}  // namespace

VoxelMeans voxel_means(std::span<const Eigen::Vector3d> points, double voxel,
                       const Eigen::Vector3d& origin) {
    if (!(voxel > 0)) throw Error("voxel centroids: the voxel size must be positive");
    std::unordered_map<std::uint64_t, std::uint32_t> index;
    VoxelMeans out;
    index.reserve(points.size() / 4 + 1);
    for (const auto& p : points) {
        std::uint64_t key = 0;
        for (int k = 0; k < 3; ++k) {
            const auto c =
                static_cast<std::int64_t>(std::floor((p(k) - origin(k)) / voxel)) + (1 << 20);
            key = (key << 21) | (static_cast<std::uint64_t>(c) & 0x1FFFFF);
        }
        const auto [it, inserted] =
            index.try_emplace(key, static_cast<std::uint32_t>(out.points.size()));
        if (inserted) {
            out.points.emplace_back(Eigen::Vector3d::Zero());
            out.counts.push_back(0.0);
        }
        out.points[it->second] += p;
        out.counts[it->second] += 1.0;
    }
    for (std::size_t i = 0; i < out.points.size(); ++i) out.points[i] /= out.counts[i];
    return out;
}

std::vector<Eigen::Vector3d> voxel_centroids(std::span<const Eigen::Vector3d> points, double voxel,
                                             const Eigen::Vector3d& origin) {
    return voxel_means(points, voxel, origin).points;
}

SurfaceSample surface_with_normals(std::span<const Eigen::Vector3d> points, double radius,
                                   double max_curvature, const Eigen::Vector3d& viewpoint,
                                   std::span<const double> counts, double min_direction_spread,
                                   double min_points) {
    SurfaceSample out;
    if (points.empty()) return out;
    if (!counts.empty() && counts.size() != points.size())
        throw Error("surface normals: as many counts as points expected");
    const auto count = [&](std::size_t j) { return counts.empty() ? 1.0 : counts[j]; };
    const Eigen::Vector3d origin = centroid(points);
    const auto xyz = xyz_cloud(points, origin);
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    tree.setInputCloud(xyz);
    std::vector<int> k;
    std::vector<float> d2;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (tree.radiusSearch((*xyz)[i], radius, k, d2) < kMinNeighbours) continue;
        // The neighbours' covariance in double, about their mean (Hoppe et al. 1992), each
        // weighing the scan points it stands for.
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        double w = 0;
        for (const int j : k) {
            const auto u = static_cast<std::size_t>(j);
            mean += count(u) * points[u];
            w += count(u);
        }
        if (w < min_points) continue;  // the scan points the neighbours stand for
        mean /= w;
        Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
        for (const int j : k) {
            const auto u = static_cast<std::size_t>(j);
            const Eigen::Vector3d d = points[u] - mean;
            C += count(u) * d * d.transpose();
        }
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
        const Eigen::Vector3d l = es.eigenvalues().cwiseMax(0.0);  // ascending
        const double total = l.sum();
        // A plane spreads in two directions: neighbours along a line (one scan row on
        // grazing ground, an edge) leave the normal undetermined about that line.
        if (!(total > 0) || l(0) / total > max_curvature || l(1) < kMinSpread * l(2)) continue;
        if (min_direction_spread > 0 &&
            direction_spread(points, k, viewpoint, count) < min_direction_spread) {
            continue;
        }
        Eigen::Vector3d n = es.eigenvectors().col(0).normalized();
        if (n.dot(viewpoint - points[i]) < 0) n = -n;
        out.points.push_back(points[i]);
        out.normals.push_back(n);
        out.plane_offsets.push_back(n.dot(points[i] - mean));
        if (!counts.empty()) out.counts.push_back(counts[i]);
    }
    return out;
}

IcpAlignment align_point_to_plane(const SurfaceSample& epoch_sample, const SurfaceSample& reference,
                                  const NearestPoints& nearest, const Eigen::Matrix4d& start,
                                  const IcpParams& params, std::span<const std::uint8_t> on_plane) {
    const std::vector<Eigen::Vector3d>& epoch = epoch_sample.points;
    if (epoch.empty() || reference.points.empty()) {
        throw Error("ICP: no points in the stable regions (epoch " + std::to_string(epoch.size()) +
                    ", reference " + std::to_string(reference.points.size()) + ")");
    }
    // X = R·x + t becomes X' = R·x' + (R·o + t − o) about the origin o.
    const Eigen::Vector3d o = centroid(reference.points);
    const Eigen::Matrix3d R0 = start.topLeftCorner<3, 3>();
    Eigen::Matrix4d local = start;
    local.topRightCorner<3, 1>() = R0 * o + start.topRightCorner<3, 1>() - o;

    const Cloud::Ptr source = to_cloud(epoch, o);
    const Cloud::Ptr target = to_cloud(reference.points, o, &reference.normals);
    CountingIcp icp;
    icp.setInputSource(source);
    icp.setInputTarget(target);
    icp.setMaxCorrespondenceDistance(params.max_correspondence_distance);
    icp.setMaximumIterations(params.max_iterations);
    // A step's translation below the epsilon ends the iterations (PCL compares it squared);
    // the rotation's cosine is always 1 in float at arc-second steps, so it does not decide.
    icp.setTransformationEpsilon(params.translation_epsilon * params.translation_epsilon);
    icp.setTransformationRotationEpsilon(1.0 - 1e-12);
    Cloud aligned;
    icp.align(aligned, local.cast<float>());

    IcpAlignment out;
    out.iterations = icp.iterations();
    out.converged = icp.hasConverged();
    const Eigen::Matrix4d L = icp.getFinalTransformation().cast<double>();
    const Eigen::Matrix3d R = L.topLeftCorner<3, 3>();
    out.transform = L;
    out.transform.topRightCorner<3, 1>() = L.topRightCorner<3, 1>() + o - R * o;

    out.pairs = point_plane_pairs(epoch_sample, reference, nearest, out.transform,
                                  params.max_correspondence_distance, on_plane);
    out.overlap = static_cast<double>(out.pairs.size()) / static_cast<double>(epoch.size());
    return out;
}

std::vector<std::uint32_t> supervoxel_labels(std::span<const Eigen::Vector3d> points,
                                             const SupervoxelParams& params) {
    if (points.empty()) throw Error("supervoxels: no points");
    const Eigen::Vector3d origin = centroid(points);
    const auto xyz = xyz_cloud(points, origin);
    pcl::SupervoxelClustering<pcl::PointXYZ> vccs(static_cast<float>(params.voxel),
                                                  static_cast<float>(params.seed));
    vccs.setUseSingleCameraTransform(false);
    vccs.setColorImportance(0.0f);
    vccs.setSpatialImportance(static_cast<float>(params.spatial_importance));
    vccs.setNormalImportance(static_cast<float>(params.normal_importance));
    vccs.setInputCloud(xyz);
    std::map<std::uint32_t, pcl::Supervoxel<pcl::PointXYZ>::Ptr> clusters;
    vccs.extract(clusters);
    // getLabeledCloud keeps the input's order: one label per input point.
    const auto labelled = vccs.getLabeledCloud();
    std::vector<std::uint32_t> labels(points.size(), 0);
    for (std::size_t i = 0; i < points.size() && i < labelled->size(); ++i) {
        labels[i] = (*labelled)[i].label;
    }
    return labels;
}

struct NearestPoints::Tree {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
};

NearestPoints::NearestPoints(std::span<const Eigen::Vector3d> points)
    : tree_(std::make_unique<Tree>()) {
    if (points.empty()) return;
    tree_->origin = centroid(points);
    tree_->tree.setInputCloud(xyz_cloud(points, tree_->origin));
}

NearestPoints::~NearestPoints() = default;

std::int64_t NearestPoints::nearest(const Eigen::Vector3d& query, double max_distance) const {
    if (!tree_->tree.getInputCloud()) return -1;
    const Eigen::Vector3d q = query - tree_->origin;
    std::vector<int> k(1);
    std::vector<float> d2(1);
    const pcl::PointXYZ p(static_cast<float>(q.x()), static_cast<float>(q.y()),
                          static_cast<float>(q.z()));
    if (tree_->tree.nearestKSearch(p, 1, k, d2) != 1) return -1;
    if (d2[0] > max_distance * max_distance) return -1;
    return k[0];
}

std::vector<registration::PointPlanePair> point_plane_pairs(
    const SurfaceSample& epoch, const SurfaceSample& reference, const NearestPoints& nearest,
    const Eigen::Matrix4d& T, double max_distance, std::span<const std::uint8_t> on_plane) {
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = T.topRightCorner<3, 1>();
    std::vector<registration::PointPlanePair> pairs;
    pairs.reserve(epoch.points.size());
    for (std::size_t i = 0; i < epoch.points.size(); ++i) {
        const Eigen::Vector3d& x = epoch.points[i];
        const std::int64_t j = nearest.nearest(R * x + t, max_distance);
        if (j < 0) continue;
        const auto u = static_cast<std::size_t>(j);
        const double weight = epoch.counts.empty() ? 1.0 : epoch.counts[i];
        if (!on_plane.empty() && on_plane[u]) {
            pairs.push_back({epoch.foot(i), reference.foot(u), reference.normals[u], weight});
        } else {
            pairs.push_back({x, reference.points[u], reference.normals[u], weight});
        }
    }
    return pairs;
}

}  // namespace tlsmon
