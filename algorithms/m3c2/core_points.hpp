#pragma once
// Core points: where M3C2 measures (Lague 2013, "core points" of the reference cloud). Taken
// once from the reference by spatial subsampling at a spacing S: the cloud is cut into cubes
// of edge S aligned on multiples of S, and each occupied cube gives the point nearest its
// centre (the lowest index on ties). They come in the cloud's order (ascending index).
#include <Eigen/Core>
#include <vector>

namespace tlsmon::m3c2 {

std::vector<Eigen::Vector3d> subsample(const std::vector<Eigen::Vector3d>& cloud, double spacing,
                                       unsigned threads = 0);

}  // namespace tlsmon::m3c2
