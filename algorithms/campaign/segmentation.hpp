#pragma once
// The two-stage segmentation of the segment-based comparison (Blaskow & Maas, see
// verticality.hpp): Euclidean clustering of the cloud with a distance adapted to its mean
// point spacing (objects: a pier, the deck, an abutment), then each cluster split by
// verticality class into connected parts (a pier's faces apart from the deck's soffit
// joining it). Stage 2 links two points only when they are within the distance and of one
// class, so each segment lies inside one cluster.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/campaign/verticality.hpp"

namespace tlsmon::campaign {

struct SegmentationParameters {
    double distance_factor = 3.0;  // clustering distance = this × the mean point spacing
    int min_points = 50;           // a smaller segment is left unsegmented
    int spacing_samples = 20000;   // points the mean spacing is estimated from, at most
};

struct Segment {
    VerticalityClass kind = VerticalityClass::other;
    std::int32_t cluster = 0;  // its stage-1 cluster
    std::size_t points = 0;
    // Of a thinned cloud (pipeline/campaign_comparison.hpp): its voxels, while `points` counts
    // the points they stand for. Otherwise equal to `points`.
    std::size_t voxels = 0;
};

struct Segmentation {
    double spacing = 0;                 // m, mean nearest-neighbour distance
    double distance = 0;                // m, the clustering distance
    std::vector<std::int32_t> cluster;  // per point, stage 1; −1: not finite
    std::vector<std::int32_t> segment;  // per point, index into `segments`; −1: none
    std::vector<Segment> segments;      // largest first
    std::size_t clusters = 0;
};

// The mean distance from a point to its nearest neighbour over up to `samples` points taken
// evenly through the cloud; 0 for fewer than two points.
double mean_spacing(std::span<const Eigen::Vector3d> points, int samples);

// `classes`: per point (classify(verticality(...))); an undefined point joins "other". The
// result does not depend on `threads` (0: every core).
Segmentation segment_cloud(std::span<const Eigen::Vector3d> points,
                           std::span<const VerticalityClass> classes,
                           const SegmentationParameters& parameters, unsigned threads = 0);

void validate(const SegmentationParameters& parameters);

}  // namespace tlsmon::campaign
