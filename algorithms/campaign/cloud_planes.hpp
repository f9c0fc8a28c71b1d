#pragma once
// The planes of an unstructured cloud (a campaign's walk, or a reference taken as points): the
// observations of the coarse registration that brings a campaign's own SLAM frame to the
// reference's (plane_matching_without_prior.hpp). Region growing under a plane constraint,
// after Rabbani, van den Heuvel & Vosselman (2006), "Segmentation of point clouds using
// smoothness constraint" — but a region's points must lie on the region's plane, not only
// turn smoothly from one to the next, so that a curved or chamfered surface is not taken for
// one plane (PCL's RegionGrowing tests the smoothness alone):
//
// 1. The cloud thinned to one point per `spacing` voxel (thinning.hpp); each kept point's
//    local plane (local_plane.hpp) from its kept neighbours within `radius`.
// 2. Seeds in the order of their surface variation, flattest first (a point whose variation
//    exceeds `max_variation` seeds nothing and joins nothing: an edge, a bush). A region grows
//    over the points within `grow_distance` of one of its points whose local normal lies
//    within `max_angle_deg` of the region's normal (either sign) and who lie within
//    `max_offset` of the region's plane — the seed's local plane, fitted again on the region's
//    points each time it has doubled.
// 3. A region of at least `min_points` points whose in-plane RMS extent is at least
//    `min_extent` along both axes is fitted (plane_fit.hpp) with its points' own scatter as σ.
//    Its normal's sign means nothing (no scanner to face).
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

#include "algorithms/registration/plane_fit.hpp"

namespace tlsmon::campaign {

struct CloudPlaneParameters {
    double spacing = 0.10;        // m, the voxel the cloud is thinned to
    double radius = 0.30;         // m, the local planes' neighbourhood
    int min_neighbours = 8;       // of a local plane
    double max_variation = 0.02;  // λ3/Σλ of a point that seeds or joins a region
    double grow_distance = 0.25;  // m, a region's reach from each of its points
    double max_angle_deg = 10.0;  // a point's normal from the region's
    double max_offset = 0.08;     // m, a point from the region's plane
    std::size_t min_points = 150;
    double min_extent = 0.3;       // m, the RMS extent along the plane's shorter axis
    std::size_t max_planes = 100;  // the largest are kept
};

// The cloud's planes, largest (most thinned points) first. The result does not depend on
// `threads` (0: every core).
std::vector<registration::FittedPlane> detect_cloud_planes(std::span<const Eigen::Vector3d> points,
                                                           const CloudPlaneParameters& parameters,
                                                           unsigned threads = 0);

void validate(const CloudPlaneParameters& parameters);

}  // namespace tlsmon::campaign
