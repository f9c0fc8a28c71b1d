#pragma once
// Core points: where M3C2 measures (Lague 2013, "core points" of the reference cloud). Taken
// once from the reference by spatial subsampling at a spacing S: the cloud is cut into cubes
// of edge S aligned on multiples of S, and each occupied cube gives the point nearest its
// centre (the lowest index on ties). A surface lying on a layer of cube faces (a wall at
// y = 45 m with S = 0.5 m) occupies the cubes on both sides and would give two core points a
// few millimetres apart, counted twice in a zone's mean; so a candidate closer than S/2 to
// one kept before it is dropped, the candidates taken nearest-to-their-centre first (then by
// index). They come in the cloud's order (ascending index).
#include <Eigen/Core>
#include <vector>

namespace tlsmon::m3c2 {

std::vector<Eigen::Vector3d> subsample(const std::vector<Eigen::Vector3d>& cloud, double spacing,
                                       unsigned threads = 0);

}  // namespace tlsmon::m3c2
