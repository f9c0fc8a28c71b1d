#pragma once
// Cloud-to-cloud (C2C) distances of a campaign cloud's points to the TLS reference, after the
// segment-wise registration, as CloudCompare computes them: to the nearest reference point,
// or — the local model — to the local plane there (least squares plane of its neighbours,
// local_plane.hpp), which removes the reference's sampling from the distance: on a surface
// sampled every s, the nearest point is up to s/√2 away along the surface even when the
// surfaces coincide. Where the local plane is no model of the surface (an edge: the
// reference surface's max_variation) the local model falls back to the nearest point. Each
// distance with its X, Y, Z components (the vector from the point to
// its counterpart), per point like M3C2's arrays, and summarised per segment.
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

#include "algorithms/campaign/reference_surface.hpp"

namespace tlsmon::campaign {

enum class C2cModel { nearest_point, local_plane };

// The vector from a campaign point to its counterpart in the reference, m (NaN: no reference
// point within the surface's max_distance).
std::vector<Eigen::Vector3f> c2c_vectors(const ReferenceSurface& reference,
                                         std::span<const Eigen::Vector3d> points, C2cModel model,
                                         unsigned threads = 0);

struct C2cStatistics {
    std::size_t points = 0;                                 // with a distance
    std::size_t missing = 0;                                // without
    double mean = 0;                                        // m, of the distances |v|
    double sigma = 0;                                       // m, their standard deviation
    double rms = 0;                                         // m
    double median = 0, p95 = 0, max = 0;                    // m
    Eigen::Vector3d mean_vector = Eigen::Vector3d::Zero();  // m, the components' means
};

C2cStatistics summarise(std::span<const Eigen::Vector3f> vectors);

}  // namespace tlsmon::campaign
