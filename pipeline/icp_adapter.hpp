#pragma once
// The one adapter to the Point Cloud Library (PCL 1.13): its headers are included by
// icp_adapter.cpp alone (they cost about a minute per translation unit), and everything here
// speaks plain Eigen. It thins a cloud to voxel centroids, estimates the reference surface's
// normals, and runs PCL's point-to-plane ICP (IterativeClosestPointWithNormals with the
// linear least-squares point-to-plane estimation, Low 2004), returning the final pairs for the
// adjustment and covariance of algorithms/registration/point_to_plane.hpp.
//
// PCL works in float: both clouds are taken about the reference sample's centroid first, so a
// coordinate of a site a few hundred metres across keeps about 0.01 mm.
#include <Eigen/Core>
#include <span>
#include <vector>

#include "algorithms/registration/point_to_plane.hpp"

namespace tlsmon {

// Points of a surface with their unit normals (same order, same count).
struct SurfaceSample {
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector3d> normals;
};

// One centroid per occupied cube of side `voxel` (cells aligned on the origin).
std::vector<Eigen::Vector3d> voxel_centroids(std::span<const Eigen::Vector3d> points, double voxel);

// Normals by principal component analysis of the neighbours within `radius` (Hoppe et al.
// 1992), turned towards `viewpoint`. A point is dropped when its surface variation
// λ₀/(λ₀ + λ₁ + λ₂) exceeds `max_curvature` (an edge, a corner, vegetation), or its
// neighbours are fewer than 6 or lie along a line (λ₁ < 0.05·λ₂: one scan row on grazing
// ground): point-to-plane distances mean nothing there.
SurfaceSample surface_with_normals(std::span<const Eigen::Vector3d> points, double radius,
                                   double max_curvature, const Eigen::Vector3d& viewpoint);

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

// Throws tlsmon::Error when either cloud is empty.
IcpAlignment align_point_to_plane(std::span<const Eigen::Vector3d> epoch,
                                  const SurfaceSample& reference, const Eigen::Matrix4d& start,
                                  const IcpParams& params);

}  // namespace tlsmon
