#pragma once
// The one adapter to the Point Cloud Library (PCL 1.13): its headers are included by
// pcl_adapter.cpp alone (they cost about a minute per translation unit), and everything here
// speaks plain Eigen. It thins a cloud to voxel centroids, estimates the reference surface's
// normals, runs PCL's point-to-plane ICP (IterativeClosestPointWithNormals with the linear
// least-squares point-to-plane estimation, Low 2004), returning the final pairs for the
// adjustment and covariance of algorithms/registration/point_to_plane.hpp, over-segments a
// cloud into supervoxels (VCCS, Papon et al. 2013) and finds nearest points (a k-d tree).
//
// PCL works in float: both clouds are taken about the reference sample's centroid first, so a
// coordinate of a site a few hundred metres across keeps about 0.01 mm.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "algorithms/registration/point_to_plane.hpp"

namespace tlsmon {

// Points of a surface with their unit normals (same order, same count), and, when the points
// are voxel means, how many scan points each stands for (empty: one each). Each point's
// distance from its neighbours' plane along its normal, nᵀ·(p − mean): its foot on that plane
// is p − offset·n (empty where not computed).
struct SurfaceSample {
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector3d> normals;
    std::vector<double> counts;
    std::vector<double> plane_offsets;
    Eigen::Vector3d foot(std::size_t i) const { return points[i] - plane_offsets[i] * normals[i]; }
};

// The mean of the points in each occupied cube of side `voxel` (cells aligned on `origin`),
// with their number.
//
// A voxel's mean is not a point of the surface: a surface near a voxel face is cut along
// itself, each side holding only the points its noise took there, so each mean lies off the
// surface by up to 0.8 σ, and by an amount that changes as the drift moves the surface against
// the grid. The count-weighted sum over both sides, which is the sum of the points themselves,
// is free of that (surface_with_normals, the ICP's pair weights).
struct VoxelMeans {
    std::vector<Eigen::Vector3d> points;
    std::vector<double> counts;
};
VoxelMeans voxel_means(std::span<const Eigen::Vector3d> points, double voxel,
                       const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

// voxel_means' points alone.
std::vector<Eigen::Vector3d> voxel_centroids(
    std::span<const Eigen::Vector3d> points, double voxel,
    const Eigen::Vector3d& origin = Eigen::Vector3d::Zero());

// Normals by principal component analysis of the neighbours within `radius` (Hoppe et al.
// 1992), turned towards `viewpoint`. A point is dropped when its surface variation
// λ₀/(λ₀ + λ₁ + λ₂) exceeds `max_curvature` (an edge, a corner, vegetation), or its
// neighbours are fewer than 6 or lie along a line (λ₁ < 0.05·λ₂: one scan row on grazing
// ground): point-to-plane distances mean nothing there.
// With `counts` (voxel means), each neighbour weighs as many points as it stands for, so the
// plane is the one through the scan points themselves; the kept points' counts are returned.
// With `min_direction_spread` (rad), a point is also dropped when its neighbours' directions
// from `viewpoint` spread less than that across their widest spread: the points of one scan
// row lie in that row's cone of beams however their ranges scatter, and on grazing ground the
// angular noise scatters them along the beams into what looks like a plane.
// With `min_points`, a point is also dropped when its neighbours stand for fewer scan points
// than that (by `counts`): where the scan is coarser than the voxels, each mean is one beam's
// point and a few of them make a plane that leans towards their rows' cones.
SurfaceSample surface_with_normals(std::span<const Eigen::Vector3d> points, double radius,
                                   double max_curvature, const Eigen::Vector3d& viewpoint,
                                   std::span<const double> counts = {},
                                   double min_direction_spread = 0.0, double min_points = 0.0);

struct IcpParams {
    double max_correspondence_distance = 0.05;  // m
    int max_iterations = 50;
    double translation_epsilon = 1e-5;  // m, a step smaller than this ends the iterations
};

struct IcpAlignment {
    Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // epoch -> reference
    int iterations = 0;
    bool converged = false;
    // Each epoch point with its nearest reference point within the correspondence distance
    // under `transform`, and that point's normal.
    std::vector<registration::PointPlanePair> pairs;
    double overlap = 0.0;  // pairs / epoch points
};

class NearestPoints;

// Each pair weighs the epoch point's count when the epoch sample has counts (voxel means);
// `nearest` indexes the reference's points, `on_plane` as point_plane_pairs takes it. Throws
// tlsmon::Error when either cloud is empty.
IcpAlignment align_point_to_plane(const SurfaceSample& epoch, const SurfaceSample& reference,
                                  const NearestPoints& nearest, const Eigen::Matrix4d& start,
                                  const IcpParams& params,
                                  std::span<const std::uint8_t> on_plane = {});

// Voxel Cloud Connectivity Segmentation (Papon et al. 2013, PCL's SupervoxelClustering): the
// cloud voxelised at `voxel`, seeds on a grid of `seed`, each supervoxel grown over adjacent
// voxels by a distance of spatial separation (relative to `seed`), and normal difference.
// Without the single-camera transform: a scanner's points are not a depth image.
struct SupervoxelParams {
    double voxel = 0.10;  // m
    double seed = 1.0;    // m
    double spatial_importance = 0.4;
    double normal_importance = 1.0;
};

// One label per point, 1.. per supervoxel; 0: in none (a voxel the growth did not reach).
// Throws tlsmon::Error when the points are empty.
std::vector<std::uint32_t> supervoxel_labels(std::span<const Eigen::Vector3d> points,
                                             const SupervoxelParams& params);

// The nearest of a fixed set of points (a k-d tree, taken about the set's centroid in float
// as the ICP does). Queries are const and may run from several threads at once.
class NearestPoints {
  public:
    explicit NearestPoints(std::span<const Eigen::Vector3d> points);
    ~NearestPoints();
    NearestPoints(const NearestPoints&) = delete;
    NearestPoints& operator=(const NearestPoints&) = delete;
    // The index of the nearest point within `max_distance` of `query`, or −1.
    std::int64_t nearest(const Eigen::Vector3d& query, double max_distance) const;

  private:
    struct Tree;
    std::unique_ptr<Tree> tree_;
};

// Each epoch point with its nearest reference point within `max_distance` under `T` (epoch ->
// reference; `nearest` indexes the reference's points), that point's normal and the epoch
// point's count as its weight: the pairs align_point_to_plane returns, made under any T.
// Where `on_plane` (one flag per reference point, or empty) is set for the reference point,
// the pair joins both points' feet on their neighbours' planes (SurfaceSample::foot).
std::vector<registration::PointPlanePair> point_plane_pairs(
    const SurfaceSample& epoch, const SurfaceSample& reference, const NearestPoints& nearest,
    const Eigen::Matrix4d& T, double max_distance, std::span<const std::uint8_t> on_plane = {});

}  // namespace tlsmon
